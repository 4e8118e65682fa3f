// A tiny scene for text-query and evaluation tests: two opaque round Gaussians side by side, seen
// by a 64x48 camera at the origin; instance 0 is the left one, instance 1 the right one.
#pragma once

#include <cmath>

#include "nodes/scene/camera.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "tests/pinhole.hpp"

namespace gslift::test {

inline Camera query_camera() {
  return centred_pinhole(64, 48, 60);
}

inline GaussianModel two_blobs() {
  GaussianModel m;
  m.resize(2);
  const float xs[2] = {-0.5f, 0.5f};  // pixel columns 17 and 47 at z = 2
  for (int g = 0; g < 2; ++g) {
    m.means[3 * g + 0] = xs[g];
    m.means[3 * g + 2] = 2.f;
    for (int a = 0; a < 3; ++a) m.log_scales[3 * g + a] = std::log(0.15f);  // 4.5 px sigma
    m.opacity_logits[g] = 4.f;
  }
  m.instance_ids = {0, 1};
  return m;
}

}  // namespace gslift::test
