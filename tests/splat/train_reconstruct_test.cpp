// A tiny reconstruction end to end: targets rendered from a known Gaussian scene, then trained
// back from its depth; PSNR floor, loss decrease, switchable terms and thread-count determinism.
#include <cmath>
#include <random>

#include <tbb/global_control.h>

#include "nodes/splat/rasterizer.hpp"
#include "nodes/splat/reconstruct.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

// A coloured floor (flat Gaussians on z = 0) with a few round blobs above it.
GaussianModel ground_truth_scene() {
  GaussianModel m;
  const int grid = 14;
  m.resize(grid * grid + 6);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  for (int i = 0; i < grid * grid; ++i) {
    const float x = -1.f + 2.f * (i % grid + 0.5f) / grid,
                y = -1.f + 2.f * (i / grid + 0.5f) / grid;
    m.means[i * 3] = x;
    m.means[i * 3 + 1] = y;
    m.log_scales[i * 3] = m.log_scales[i * 3 + 1] = std::log(0.1f);
    m.log_scales[i * 3 + 2] = std::log(0.01f);
    m.opacity_logits[i] = 4.f;
    for (int c = 0; c < 3; ++c) m.sh[i * 3 + c] = (u(rng) - 0.5f) / 0.2821f * 0.8f;
  }
  for (int b = 0; b < 6; ++b) {
    const int i = grid * grid + b;
    m.means[i * 3] = -0.6f + 0.25f * b;
    m.means[i * 3 + 1] = 0.3f * std::sin(b * 1.3f);
    m.means[i * 3 + 2] = 0.2f;
    for (int k = 0; k < 3; ++k) m.log_scales[i * 3 + k] = std::log(0.12f);
    m.opacity_logits[i] = 4.f;
    for (int c = 0; c < 3; ++c) m.sh[i * 3 + c] = (u(rng) - 0.5f) / 0.2821f;
  }
  return m;
}

// 5 cameras on a ring above the scene looking at the origin; the last one is held out.
Capture rendered_capture() {
  const GaussianModel truth = ground_truth_scene();
  Capture c;
  c.name = "tiny";
  for (int k = 0; k < 5; ++k) {
    View v;
    v.name = "cam_" + std::to_string(k);
    v.camera.width = 64;
    v.camera.height = 48;
    v.camera.fx = v.camera.fy = 60;
    v.camera.cx = 32;
    v.camera.cy = 24;
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

ReconstructOptions tiny_options() {
  ReconstructOptions o;
  o.iterations = 300;
  o.init.pixel_stride = 1;
  o.init.footprint_factor = 2;
  o.seed = 5;
  return o;
}

}  // namespace

TEST_CASE("a tiny reconstruction reaches a PSNR floor and lowers its loss") {
  const Capture capture = rendered_capture();
  int calls = 0, last_total = 0;
  const ReconstructResult r = reconstruct(capture, tiny_options(), [&](int, int total, double) {
    ++calls;
    last_total = total;
  });
  CHECK(calls == 300);
  CHECK(last_total == 300);
  CHECK(r.iterations_run == 300);
  CHECK(r.initial_gaussians > 100);
  CHECK(r.model.size() > 0);
  const auto& h = r.loss_history;
  const double first = (h[0] + h[1] + h[2] + h[3]) / 4;
  INFO("initial loss " << first << " final " << r.final_loss.total << " train PSNR " << r.train_psnr
                       << " test PSNR " << r.test_psnr << " gaussians " << r.model.size());
  CHECK(r.final_loss.total < 0.5 * first);
  CHECK(r.train_psnr > 32.0);
  CHECK(r.test_psnr > 24.0);
  CHECK(r.final_loss.depth > 0);
  CHECK(r.final_loss.normal > 0);
}

TEST_CASE("reconstruction is identical at 1 and 2 threads, and loss terms switch off") {
  const Capture capture = rendered_capture();
  ReconstructOptions o = tiny_options();
  o.iterations = 120;
  ReconstructResult one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = reconstruct(capture, o);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = reconstruct(capture, o);
  }
  CHECK(one.model.means == two.model.means);
  CHECK(one.model.sh == two.model.sh);
  CHECK(one.loss_history == two.loss_history);

  o.depth_weight = o.normal_weight = o.scale_weight = 0;
  o.iterations = 20;
  const ReconstructResult off = reconstruct(capture, o);
  CHECK(off.final_loss.depth == 0);
  CHECK(off.final_loss.normal == 0);
  CHECK(off.final_loss.flatness == 0);
  CHECK(off.final_loss.total == Approx(off.final_loss.photometric));
}

TEST_CASE("early stop ends a run whose loss has plateaued") {
  const Capture capture = rendered_capture();
  ReconstructOptions o = tiny_options();
  o.iterations = 2000;
  o.plateau_window = 50;
  o.plateau_tolerance = 0.5;  // any window that does not halve the loss stops the run
  const ReconstructResult r = reconstruct(capture, o);
  CHECK(r.stopped_early);
  CHECK(r.iterations_run < 2000);
  CHECK(r.iterations_run % 50 == 0);
}
