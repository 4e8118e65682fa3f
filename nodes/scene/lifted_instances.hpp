// The 3D instances that lifting (LangOR §1.3, lifting.cvp and lifting.mask_level) hands to
// association: the clustered samples of the training masks and one prototype feature per
// instance.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "base/port_type.hpp"

namespace gslift {

struct SampledPixel {
  int view = 0;  // index into the views / MaskSet::views
  int mask = 0;  // index into that view's masks
  int x = 0;
  int y = 0;
};

struct LiftedInstances {
  // CVP: the distinct drawn pixels and their HDBSCAN labels (-1 noise).
  // Mask level: one entry per mask (x = y = -1) and the mask's label.
  std::vector<SampledPixel> samples;
  std::vector<int> labels;
  // Eq. 5: one row per instance, the mean feature of its members (noise excluded).
  Eigen::MatrixXf prototypes;
};

GSLIFT_PORT_TYPE(LiftedInstances, "LiftedInstances");

}  // namespace gslift
