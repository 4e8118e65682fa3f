// A tiny posed capture rendered from a known Gaussian scene, shared by the training tests.
#pragma once

#include <cmath>
#include <string>

#include "base/random.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "tests/pinhole.hpp"

namespace gslift::test {

// A coloured floor (flat Gaussians on z = 0) with a few round blobs above it.
inline GaussianModel ground_truth_scene() {
  GaussianModel m;
  const int grid = 14;
  m.resize(grid * grid + 6);
  RandomStream rng(3);
  auto u = [&] { return static_cast<float>(rng.uniform()); };
  for (int i = 0; i < grid * grid; ++i) {
    const float x = -1.f + 2.f * (i % grid + 0.5f) / grid,
                y = -1.f + 2.f * (i / grid + 0.5f) / grid;
    m.means[i * 3] = x;
    m.means[i * 3 + 1] = y;
    m.log_scales[i * 3] = m.log_scales[i * 3 + 1] = std::log(0.1f);
    m.log_scales[i * 3 + 2] = std::log(0.01f);
    m.opacity_logits[i] = 4.f;
    for (int c = 0; c < 3; ++c) m.sh[i * 3 + c] = (u() - 0.5f) / 0.2821f * 0.8f;
  }
  for (int b = 0; b < 6; ++b) {
    const int i = grid * grid + b;
    m.means[i * 3] = -0.6f + 0.25f * b;
    m.means[i * 3 + 1] = 0.3f * std::sin(b * 1.3f);
    m.means[i * 3 + 2] = 0.2f;
    for (int k = 0; k < 3; ++k) m.log_scales[i * 3 + k] = std::log(0.12f);
    m.opacity_logits[i] = 4.f;
    for (int c = 0; c < 3; ++c) m.sh[i * 3 + c] = (u() - 0.5f) / 0.2821f;
  }
  return m;
}

// 5 cameras on a ring above the scene looking at the origin; the last one is held out.
inline Capture rendered_capture() {
  const GaussianModel truth = ground_truth_scene();
  Capture c;
  c.name = "tiny";
  for (int k = 0; k < 5; ++k) {
    View v;
    v.name = "cam_" + std::to_string(k);
    v.camera = centred_pinhole(64, 48, 60);
    const double a = 2 * M_PI * k / 5;
    const Eigen::Vector3d eye(2.2 * std::cos(a), 2.2 * std::sin(a), 2.0);
    const Eigen::Vector3d z = (-eye).normalized();
    const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
    const Eigen::Vector3d y = z.cross(x);
    Eigen::Matrix4d c2w = Eigen::Matrix4d::Identity();
    c2w.block<3, 1>(0, 0) = x;
    c2w.block<3, 1>(0, 1) = y;
    c2w.block<3, 1>(0, 2) = z;
    c2w.block<3, 1>(0, 3) = eye;
    v.pose = Pose::from_camera_to_world(c2w);
    RenderSettings s;
    s.depth = s.alpha = true;
    RenderOutput out = render(truth, v.camera, v.pose, s);
    cv::Mat rgb(48, 64, CV_32FC3, out.rgb.data()), rgb8;
    rgb.convertTo(rgb8, CV_8UC3, 255);
    cv::Mat depth(48, 64, CV_32FC1);
    for (int p = 0; p < 48 * 64; ++p)  // normalised depth where the surface is solid, else invalid
      depth.at<float>(p) = out.alpha[p] > 0.5f ? out.depth[p] / out.alpha[p] : 0.f;
    v.rgb = ImageSource::in_memory(rgb8);
    v.depth = ImageSource::in_memory(depth);
    v.held_out = k == 4;
    c.views.push_back(v);
  }
  return c;
}

}  // namespace gslift::test
