// A small scene for feature-training tests: two groups of Gaussians, two training views with one
// mask per group, and a held-out view whose contradicting mask training must ignore.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/masks.hpp"
#include "tests/pinhole.hpp"

namespace gslift::test {

// Two groups of 20 Gaussians side by side at depth 3, seen by two 64x48 cameras; group 0 left
// (x in [-1.2, -0.3]), group 1 right (x in [0.3, 1.2]). Opacity 0.5 and scales below the spacing
// keep every Gaussian visible: a hidden one gets no gradient and keeps its random feature.
struct TwoGroups {
  GaussianModel model;
  Capture capture;
  MaskSet masks;
  std::vector<int> group;
};

inline TwoGroups two_groups() {
  TwoGroups s;
  const int per_group = 20;
  s.model.resize(2 * per_group);
  for (int i = 0; i < 2 * per_group; ++i) {
    const int g = i / per_group, k = i % per_group;
    const float x = (g == 0 ? -1.2f : 0.3f) + 0.9f * (k % 5) / 4.f;
    const float y = -0.6f + 1.2f * (k / 5) / 3.f;
    s.model.means[3 * i + 0] = x;
    s.model.means[3 * i + 1] = y;
    s.model.means[3 * i + 2] = 3.f;
    for (int c = 0; c < 3; ++c) s.model.log_scales[3 * i + c] = std::log(0.12f);
    s.model.opacity_logits[i] = 0.f;
    s.group.push_back(g);
  }
  for (int v = 0; v < 2; ++v) {
    View view;
    view.name = "v" + std::to_string(v);
    view.camera = test::centred_pinhole(64, 48, 60);
    view.pose.t = Eigen::Vector3d(0.1 * v, 0.05 * v, 0);
    s.capture.views.push_back(view);
    // u = 32 + 20 (x + t_x): the groups project left and right of the centre column.
    ViewMasks vm;
    vm.view = view.name;
    for (int g = 0; g < 2; ++g) {
      Mask m;
      m.pixels = cv::Mat1b::zeros(48, 64);
      m.pixels(cv::Rect(g == 0 ? 6 : 36, 10, 22, 28)).setTo(255);
      vm.masks.push_back(m);
    }
    s.masks.views.push_back(vm);
  }
  // A held-out view with a mask that contradicts the others: it must be ignored.
  View test = s.capture.views[0];
  test.name = "test";
  test.held_out = true;
  s.capture.views.push_back(test);
  ViewMasks bogus;
  bogus.view = "test";
  Mask all;
  all.pixels = cv::Mat1b(48, 64, uchar(255));
  bogus.masks.push_back(all);
  s.masks.views.push_back(bogus);
  return s;
}

}  // namespace gslift::test
