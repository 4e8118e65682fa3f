// Small random scenes for the rasterizer tests: Gaussians placed inside a 32x24 camera's frustum,
// with footprints of a few pixels, moderate opacities (no 0.99 clamp) and positive colours.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

#include <Eigen/Geometry>

#include "nodes/scene/camera.hpp"
#include "nodes/scene/gaussian_model.hpp"

namespace gslift::test {

struct RasterScene {
  GaussianModel model;
  Camera camera;
  Pose pose;
};

inline RasterScene random_raster_scene(int n, int sh_degree, int feature_dim, uint32_t seed,
                                       int width = 32, int height = 24) {
  std::mt19937 rng(seed);
  auto uniform = [&](double a, double b) {
    return std::uniform_real_distribution<double>(a, b)(rng);
  };
  RasterScene s;
  s.camera.width = width;
  s.camera.height = height;
  s.camera.fx = 0.9 * width;
  s.camera.fy = 0.95 * width;
  s.camera.cx = 0.5 * width + 0.3;
  s.camera.cy = 0.5 * height - 0.2;
  s.pose.R =
      Eigen::AngleAxisd(0.2, Eigen::Vector3d(0.3, -1.0, 0.4).normalized()).toRotationMatrix();
  s.pose.t = Eigen::Vector3d(0.1, -0.05, 0.2);
  s.model.sh_degree = sh_degree;
  s.model.feature_dim = feature_dim;
  s.model.resize(n);
  const int K = GaussianModel::sh_coeffs(sh_degree);
  for (int i = 0; i < n; ++i) {
    const double z = uniform(2.0, 4.0);
    const Eigen::Vector3d cam(uniform(-0.45, 0.45) * z, uniform(-0.35, 0.35) * z, z);
    const Eigen::Vector3d world = s.pose.R.transpose() * (cam - s.pose.t);
    for (int k = 0; k < 3; ++k) {
      s.model.means[3 * i + k] = float(world[k]);
      s.model.log_scales[3 * i + k] = float(std::log(uniform(0.04, 0.25)));
    }
    for (int k = 0; k < 4; ++k) s.model.quats[4 * i + k] = float(uniform(-1.0, 1.0));
    s.model.quats[4 * i] += 0.5f;
    s.model.opacity_logits[i] = float(uniform(-1.5, 1.0));
    for (int k = 0; k < K; ++k)
      for (int c = 0; c < 3; ++c)
        s.model.sh[(i * K + k) * 3 + c] = float(k == 0 ? uniform(0.0, 1.0) : uniform(-0.15, 0.15));
    for (int f = 0; f < feature_dim; ++f)
      s.model.features[i * feature_dim + f] = float(uniform(-1, 1));
  }
  return s;
}

}  // namespace gslift::test
