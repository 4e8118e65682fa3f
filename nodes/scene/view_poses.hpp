// A pose per view of a capture, by view name: the poses splat.reconstruct refined against the
// photos (nodes/splat/pose_correction.hpp), which splat.refined_capture puts into the capture the
// later stages render with.
#pragma once

#include <string>
#include <vector>

#include "base/port_type.hpp"
#include "nodes/scene/camera.hpp"

namespace gslift {

struct ViewPoses {
  std::vector<std::string> views;  // view names, the capture's order
  std::vector<Pose> poses;         // world -> camera, one per name
};

GSLIFT_PORT_TYPE(ViewPoses, "ViewPoses");

}  // namespace gslift
