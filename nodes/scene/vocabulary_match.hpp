// Mapping free text onto a vocabulary of class names through any text encoder (issue 30): the
// classes ranked by cosine similarity of their embeddings with the text's, and the best one when
// it reaches the encoder's match_threshold(). Used for user queries (inference.text_query: a query
// stands for the class it lands on) and for a live VLM's labels (vlm.query).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "nodes/scene/text_encoder.hpp"

namespace gslift {

struct ClassMatch {
  std::string name;  // the class name
  int index = -1;    // in the vocabulary
  float score = 0;   // cosine similarity
};

class VocabularyMatcher {
 public:
  // Encodes every class name once; throws InputError on an empty vocabulary.
  VocabularyMatcher(const TextEncoder& encoder, std::vector<std::string> class_names);

  // Every class, best first (ties: vocabulary order).
  std::vector<ClassMatch> rank(const std::string& text) const;
  // The best class when its score reaches the encoder's match_threshold().
  std::optional<ClassMatch> match(const std::string& text) const;
  // "no class near 'toaster' (threshold 0.50); nearest: monitor (0.12), C-arm (0.05), ..." with
  // the three nearest.
  std::string explain_miss(const std::string& text) const;

  const std::vector<std::string>& class_names() const { return names_; }
  float threshold() const { return threshold_; }

 private:
  const TextEncoder& encoder_;
  std::vector<std::string> names_;
  Eigen::MatrixXf embeddings_;  // one row per class
  float threshold_;
};

}  // namespace gslift
