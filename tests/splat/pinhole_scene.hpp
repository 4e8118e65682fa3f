// Hand-placed Gaussians before a 40x30 pinhole (focal 40) at the origin looking down +z: the scene
// of the tests of the losses that walk a render's tile lists again (line of sight, distortion).
#pragma once

#include <cmath>

#include <Eigen/Geometry>

#include "nodes/scene/gaussian_model.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "tests/pinhole.hpp"

namespace gslift::test {

struct PinholeScene {
  Camera cam = centred_pinhole(40, 30, 40);
  Pose pose;
  // Every contribution counted (min_alpha 0), so small changes never move one in or out.
  RenderOutput forward(const GaussianModel& m) const {
    RenderSettings s;
    s.rgb = false;
    s.alpha = true;
    s.min_alpha = 0;
    return render(m, cam, pose, s);
  }
  // Gaussian i centred on pixel (u, v) at depth z, isotropic scale s, opacity o.
  void place(GaussianModel& m, int i, double u, double v, double z, double s, double o) const {
    m.means[i * 3] = float((u - cam.cx) / cam.fx * z);
    m.means[i * 3 + 1] = float((v - cam.cy) / cam.fy * z);
    m.means[i * 3 + 2] = float(z);
    for (int k = 0; k < 3; ++k) m.log_scales[i * 3 + k] = float(std::log(s));
    m.quats[i * 4] = 1.f;
    m.opacity_logits[i] = float(std::log(o / (1 - o)));
  }
  // Gaussians 0 and 1 (of at least two) made anisotropic and rotated, so that a gradient check
  // reaches every quaternion and scale component.
  static void twist(GaussianModel& m) {
    const float scales1[] = {0.15f, 0.06f, 0.1f};
    for (int k = 0; k < 3; ++k) m.log_scales[3 + k] = std::log(scales1[k]);
    const Eigen::Quaternionf q =
        Eigen::Quaternionf(Eigen::AngleAxisf(0.6f, Eigen::Vector3f(0.3f, 0.2f, 1.f).normalized()));
    m.quats[4] = q.w(), m.quats[5] = q.x(), m.quats[6] = q.y(), m.quats[7] = q.z();
    m.quats[0] = 0.9f, m.quats[1] = 0.2f, m.quats[2] = -0.1f, m.quats[3] = 0.3f;
    m.log_scales[0] = std::log(0.05f);  // Gaussian 0 flat along x
  }
};

}  // namespace gslift::test
