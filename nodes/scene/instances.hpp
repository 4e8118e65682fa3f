// 3D instances of a lifted scene (LangOR §1.3): what association produces and what text queries
// and evaluation consume. Instance k is a prototype feature in the Gaussians' instance-feature
// space plus its semantics (a label and that label's text embedding).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "base/port_type.hpp"

namespace gslift {

struct InstanceSet {
  Eigen::MatrixXf prototypes;       // K x D instance prototypes (LangOR Eq. 5)
  std::vector<std::string> labels;  // K instance labels (the chosen mask label, §1.3)
  Eigen::MatrixXf semantics;        // K x E text embeddings of the instance semantics
  // For each view of the MaskSet the instances were matched against, for each of its masks: the
  // instance it was assigned to (most frequent instance among its pixels), -1 when none.
  std::vector<std::vector<int>> mask_instance;

  int size() const { return static_cast<int>(prototypes.rows()); }
};

GSLIFT_PORT_TYPE(InstanceSet, "InstanceSet");

}  // namespace gslift
