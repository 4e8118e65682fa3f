// LangOR §1.3 "Instance semantics": an instance's label and text embedding, chosen from the labels
// of the 2D masks associated with it.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "nodes/scene/text_encoder.hpp"

namespace gslift {

struct InstanceSemantics {
  std::string label;          // "" when the instance has no mask
  Eigen::VectorXf embedding;  // encoder.dim() entries; zero when the instance has no mask
};

// mask_labels: the labels of the instance's masks, in mask order (views, then masks).
// - 3 or more masks: the mask label whose embedding has the largest summed cosine to the other
//   masks' embeddings (a medoid, so a minority of mislabelled masks cannot win); ties go to the
//   earliest mask.
// - 1 or 2 masks: the paper's average of the embeddings, L2-normalised; the label is the most
//   frequent one, ties going to the earliest (with two different labels: the first).
// - no mask: empty label, zero embedding.
InstanceSemantics choose_instance_semantics(const std::vector<std::string>& mask_labels,
                                            const TextEncoder& encoder);

}  // namespace gslift
