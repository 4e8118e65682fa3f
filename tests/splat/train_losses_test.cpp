// Finite-difference checks of every training loss's gradient, and known values.
#include <cmath>
#include <random>

#include "nodes/splat/depth_normals.hpp"
#include "nodes/splat/losses.hpp"
#include "nodes/splat/ssim.hpp"
#include "tests/pinhole.hpp"
#include "tests/splat/train_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

cv::Mat random_image(int rows, int cols, int type, unsigned seed, float lo = 0.f, float hi = 1.f) {
  cv::Mat m(rows, cols, type);
  cv::RNG rng(seed);
  rng.fill(m, cv::RNG::UNIFORM, lo, hi);
  return m;
}

// Central difference of f at element i of x (as a flat float array) against the analytic grad.
template <class F>
void check_gradient(cv::Mat x, const cv::Mat& grad, F f, double h, double rel_tol,
                    const std::vector<int>& elements) {
  float* data = x.ptr<float>();
  const float* g = grad.ptr<float>();
  double max_grad;
  const cv::Mat magnitude = cv::abs(grad);
  cv::minMaxLoc(magnitude.reshape(1), nullptr, &max_grad);
  for (int i : elements) {
    const float keep = data[i];
    data[i] = keep + static_cast<float>(h);
    const double up = f(x);
    data[i] = keep - static_cast<float>(h);
    const double down = f(x);
    data[i] = keep;
    const double numeric = (up - down) / (2 * h);
    INFO("element " << i << " analytic " << g[i] << " numeric " << numeric);
    CHECK(std::abs(numeric - g[i]) <= rel_tol * (std::abs(numeric) + 0.05 * max_grad));
  }
}

std::vector<int> spread(int total, int count) {
  std::vector<int> out;
  for (int k = 0; k < count; ++k) out.push_back(static_cast<int>((k * 7919LL) % total));
  return out;
}

}  // namespace

TEST_CASE("ssim of an image with itself is 1, and lower for a different image") {
  const cv::Mat x = random_image(20, 24, CV_32FC3, 1);
  CHECK(ssim(x, x) == Approx(1.0).margin(1e-6));
  const cv::Mat y = random_image(20, 24, CV_32FC3, 2);
  CHECK(ssim(x, y) < 0.2);
}

TEST_CASE("ssim matches a direct evaluation of the windowed statistics") {
  // Independent reference: zero-padded 11x11 Gaussian window (sigma 1.5) summed explicitly per
  // channel. One channel, and three channels over several row blocks whose row counts are not
  // multiples of the rows ssim sums together.
  const auto [rows, cols, channels] =
      GENERATE(std::make_tuple(13, 15, 1), std::make_tuple(37, 29, 3));
  const int type = CV_32FC(channels);
  const cv::Mat x = random_image(rows, cols, type, 11), y = random_image(rows, cols, type, 12);
  double w1[11], norm = 0;
  for (int k = 0; k < 11; ++k) norm += w1[k] = std::exp(-(k - 5) * (k - 5) / (2 * 1.5 * 1.5));
  const double C1 = 1e-4, C2 = 9e-4;
  double total = 0;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      for (int ch = 0; ch < channels; ++ch) {
        double mx = 0, my = 0, xx = 0, yy = 0, xy = 0;
        for (int i = -5; i <= 5; ++i)
          for (int j = -5; j <= 5; ++j) {
            if (r + i < 0 || r + i >= rows || c + j < 0 || c + j >= cols) continue;
            const double w = w1[i + 5] * w1[j + 5] / (norm * norm);
            const double a = x.ptr<float>(r + i)[(c + j) * channels + ch];
            const double b = y.ptr<float>(r + i)[(c + j) * channels + ch];
            mx += w * a, my += w * b, xx += w * a * a, yy += w * b * b, xy += w * a * b;
          }
        const double sxx = xx - mx * mx, syy = yy - my * my, sxy = xy - mx * my;
        total +=
            (2 * mx * my + C1) * (2 * sxy + C2) / ((mx * mx + my * my + C1) * (sxx + syy + C2));
      }
  CHECK(ssim(x, y) == Approx(total / (rows * cols * channels)).epsilon(1e-4));
}

TEST_CASE("ssim gradient matches finite differences") {
  const cv::Mat x = random_image(18, 21, CV_32FC3, 3);
  const cv::Mat y = random_image(18, 21, CV_32FC3, 4);
  cv::Mat grad;
  ssim(x, y, &grad);
  REQUIRE(grad.size() == x.size());
  REQUIRE(grad.type() == x.type());
  check_gradient(
      x.clone(), grad, [&](const cv::Mat& v) { return ssim(v, y); }, 1e-2, 2e-2,
      spread(18 * 21 * 3, 40));
}

TEST_CASE("photometric loss value and gradient") {
  const cv::Mat x = random_image(16, 16, CV_32FC3, 5);
  const cv::Mat y = random_image(16, 16, CV_32FC3, 6);
  cv::Mat grad;
  const PhotometricLoss loss = photometric_loss(x, y, 0.2, &grad);
  CHECK(loss.l1 == Approx(cv::norm(x - y, cv::NORM_L1) / (16 * 16 * 3)));
  CHECK(loss.value == Approx(0.8 * loss.l1 + 0.2 * (1 - ssim(x, y))));
  check_gradient(
      x.clone(), grad, [&](const cv::Mat& v) { return photometric_loss(v, y, 0.2).value; }, 1e-3,
      2e-2, spread(16 * 16 * 3, 40));
  // lambda = 0 is pure L1: gradient sign / N.
  photometric_loss(x, y, 0.0, &grad);
  CHECK(std::abs(grad.at<cv::Vec3f>(3, 4)[1]) == Approx(1.0 / (16 * 16 * 3)));
}

TEST_CASE("depth log-L1 skips invalid pixels and its gradient matches finite differences") {
  cv::Mat rendered = random_image(8, 9, CV_32FC1, 7, 1.f, 3.f);
  cv::Mat target = random_image(8, 9, CV_32FC1, 8, 1.f, 3.f);
  target.at<float>(0, 0) = 0.f;
  target.at<float>(2, 5) = std::nanf("");
  // Hand value for one valid pixel: the mean of log(1+|e|) over the 70 valid pixels.
  double expected = 0;
  for (int r = 0; r < 8; ++r)
    for (int c = 0; c < 9; ++c)
      if (!((r == 0 && c == 0) || (r == 2 && c == 5)))
        expected += std::log(1 + std::abs(rendered.at<float>(r, c) - target.at<float>(r, c)));
  cv::Mat grad;
  CHECK(depth_log_l1_loss(rendered, target, &grad) == Approx(expected / 70).epsilon(1e-6));
  CHECK(grad.at<float>(0, 0) == 0.f);
  CHECK(grad.at<float>(2, 5) == 0.f);
  check_gradient(
      rendered.clone(), grad, [&](const cv::Mat& v) { return depth_log_l1_loss(v, target); }, 1e-3,
      1e-2, spread(72, 30));
  CHECK(depth_log_l1_loss(rendered, cv::Mat::zeros(8, 9, CV_32FC1)) == 0.0);
}

TEST_CASE("normal cosine loss value and gradient") {
  cv::Mat rendered = random_image(6, 7, CV_32FC3, 9, -1.f, 1.f);
  cv::Mat target = random_image(6, 7, CV_32FC3, 10, -1.f, 1.f);
  for (auto it = target.begin<cv::Vec3f>(); it != target.end<cv::Vec3f>(); ++it)
    *it = cv::normalize(*it);
  target.at<cv::Vec3f>(1, 1) = cv::Vec3f(0, 0, 0);  // invalid target
  cv::Mat grad;
  const double loss = normal_cosine_loss(rendered, target, &grad);
  double expected = 0;
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 7; ++c)
      if (!(r == 1 && c == 1)) {
        const cv::Vec3f a = rendered.at<cv::Vec3f>(r, c), b = target.at<cv::Vec3f>(r, c);
        expected += 1 - a.dot(b) / cv::norm(a);
      }
  CHECK(loss == Approx(expected / 41).epsilon(1e-5));
  check_gradient(
      rendered.clone(), grad, [&](const cv::Mat& v) { return normal_cosine_loss(v, target); }, 1e-3,
      1e-2, spread(6 * 7 * 3, 40));
  // Scaling the rendered normal does not change the cosine.
  CHECK(normal_cosine_loss(rendered * 3, target) == Approx(loss).epsilon(1e-5));
}

TEST_CASE("flatness loss is the mean smallest scale with its gradient on that axis") {
  const std::vector<float> log_scales = {std::log(0.5f), std::log(0.1f), std::log(0.3f),
                                         std::log(0.2f), std::log(0.4f), std::log(0.6f)};
  std::vector<float> grad;
  CHECK(flatness_loss(log_scales, &grad) == Approx((0.1 + 0.2) / 2).epsilon(1e-6));
  const std::vector<float> expected = {0, 0.05f, 0, 0.1f, 0, 0};
  for (size_t i = 0; i < 6; ++i) CHECK(grad[i] == Approx(expected[i]).margin(1e-7));
  // Finite differences on each entry.
  for (size_t i = 0; i < 6; ++i) {
    std::vector<float> up = log_scales, down = log_scales;
    up[i] += 1e-3f;
    down[i] -= 1e-3f;
    CHECK((flatness_loss(up) - flatness_loss(down)) / 2e-3 == Approx(grad[i]).margin(1e-4));
  }
}

TEST_CASE("normals from the depth of a tilted plane are the plane normal, facing the camera") {
  const Camera cam = test::centred_pinhole(40, 30, 50);
  // Plane n . X = c with n = normalise(0.3, -0.2, -1): depth d = c / (n . ray).
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.2, -1).normalized();
  const double c = -2.0;
  cv::Mat depth(cam.height, cam.width, CV_32FC1);
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      const Eigen::Vector3d ray((u + 0.5 - cam.cx) / cam.fx, (v + 0.5 - cam.cy) / cam.fy, 1);
      depth.at<float>(v, u) = static_cast<float>(c / n.dot(ray));
    }
  depth.at<float>(10, 10) = 0.f;  // a hole: its neighbours lose their normal
  // A camera rotated by R about the world: world-space normals are R^T n.
  Pose pose;
  pose.R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  pose.t = Eigen::Vector3d(0.5, -1, 2);
  const cv::Mat normals = normals_from_depth(depth, cam, pose);
  const Eigen::Vector3d world = pose.R.transpose() * n;
  const cv::Vec3f centre = normals.at<cv::Vec3f>(20, 30);
  CHECK(centre[0] == Approx(world.x()).margin(1e-4));
  CHECK(centre[1] == Approx(world.y()).margin(1e-4));
  CHECK(centre[2] == Approx(world.z()).margin(1e-4));
  CHECK(cv::norm(normals.at<cv::Vec3f>(0, 5)) == 0.0);    // border
  CHECK(cv::norm(normals.at<cv::Vec3f>(10, 11)) == 0.0);  // next to the hole
  CHECK(cv::norm(normals.at<cv::Vec3f>(10, 10)) == 0.0);  // the hole
}

TEST_CASE("rendered normals of a flat scene agree with the normals of its rendered depth") {
  // The floor of the training scene alone (flat discs on z = 0, shortest axis z), seen obliquely:
  // the rendered normal and the normal derived from the rendered depth must be the same world
  // vector (+z, facing the camera above), so the loss is near 0. This pins the conventions the
  // reconstruction relies on (world frame, camera-facing sign, normalisation inside the loss).
  GaussianModel floor = test::ground_truth_scene();
  floor.resize(14 * 14);
  const Capture capture = test::rendered_capture();
  const View& view = capture.views[0];
  RenderSettings s;
  s.depth = s.alpha = s.normal = true;
  RenderOutput out = render(floor, view.camera, view.pose, s);
  const int H = out.height, W = out.width;
  cv::Mat depth(H, W, CV_32FC1);
  for (int p = 0; p < H * W; ++p)
    depth.at<float>(p) = out.alpha[p] > 0.99f ? out.depth[p] / out.alpha[p] : 0.f;
  const cv::Mat target = normals_from_depth(depth, view.camera, view.pose);
  const cv::Mat rendered(H, W, CV_32FC3, out.normal.data());
  int valid = 0;
  for (int p = 0; p < H * W; ++p) valid += target.at<cv::Vec3f>(p)[2] > 0.99f;
  CHECK(valid > H * W / 4);  // the floor fills much of the view and its prior normal is +z
  CHECK(normal_cosine_loss(rendered, target) < 0.01);

  // The same discs made isotropic: the shortest axis is arbitrary (x on ties), the loss is large.
  for (float& v : floor.log_scales) v = std::log(0.05f);
  RenderOutput round = render(floor, view.camera, view.pose, s);
  CHECK(normal_cosine_loss(cv::Mat(H, W, CV_32FC3, round.normal.data()), target) > 0.5);
}

TEST_CASE("smoothing a noisy depth prior brings its normals back to the surface's") {
  Camera cam;
  cam.width = 80;
  cam.height = 60;
  cam.fx = cam.fy = 100;
  cam.cx = 40;
  cam.cy = 30;
  // The plane z = 2 seen head-on (normal (0,0,-1)) with 2% multiplicative depth noise and a hole.
  cv::Mat depth(cam.height, cam.width, CV_32FC1);
  cv::RNG rng(7);
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u)
      depth.at<float>(v, u) = static_cast<float>(2.0 * (1 + 0.02 * rng.gaussian(1.0)));
  depth.at<float>(30, 40) = 0.f;
  const cv::Mat smooth = smooth_valid_depth(depth, 3.0);
  CHECK(smooth.at<float>(30, 40) == 0.f);  // holes stay holes
  CHECK(smooth.at<float>(30, 41) == Approx(2.0).epsilon(0.01));
  cv::Mat exact(cam.height, cam.width, CV_32FC3, cv::Scalar(0, 0, -1));
  const double raw = normal_cosine_loss(normals_from_depth(depth, cam, Pose()), exact);
  const double smoothed =
      normal_cosine_loss(normals_from_depth(depth, cam, Pose(), 0.1, 1, 3.0), exact);
  INFO("raw " << raw << " smoothed " << smoothed);
  CHECK(raw > 0.3);
  CHECK(smoothed < 0.25 * raw);
  // A longer baseline averages the noise too.
  CHECK(normal_cosine_loss(normals_from_depth(depth, cam, Pose(), 0.1, 4), exact) < 0.5 * raw);
}
