#include "nodes/splat/pose_correction.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include <Eigen/Geometry>

namespace gslift {

Pose corrected_pose(const Pose& pose, const PoseGradient& delta) {
  const Eigen::Vector3d w = delta.head<3>();
  const double angle = w.norm();
  const Eigen::Matrix3d rotation = angle > 0
                                       ? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix()
                                       : Eigen::Matrix3d::Identity();
  Pose out;
  out.R = rotation * pose.R;
  out.t = rotation * pose.t + delta.tail<3>();
  return out;
}

PoseChange pose_change(const Pose& written, const Pose& refined) {
  const Eigen::AngleAxisd relative(refined.R * written.R.transpose());
  return {std::abs(relative.angle()) * 180.0 / M_PI, (refined.centre() - written.centre()).norm()};
}

PoseOptimiser::PoseOptimiser(double rotation_rate, double translation_rate, AdamSettings settings)
    : adam_(6, settings) {
  for (int k = 0; k < 3; ++k) {
    rates_[k] = static_cast<float>(rotation_rate);
    rates_[3 + k] = static_cast<float>(translation_rate);
  }
}

void PoseOptimiser::step(Pose& pose, const PoseGradient& grad) {
  // Adam moves a zero correction; the result is applied to the pose (the gradient is always
  // taken at a zero correction of the current pose).
  float delta[6] = {0, 0, 0, 0, 0, 0};
  float g[6];
  for (int k = 0; k < 6; ++k) g[k] = static_cast<float>(grad[k]);
  adam_.step(delta, g, 1, rates_);
  PoseGradient d;
  for (int k = 0; k < 6; ++k) d[k] = delta[k];
  pose = corrected_pose(pose, d);
}

Pose refine_pose_to_photo(const GaussianModel& model, const Camera& camera, const Pose& pose,
                          const cv::Mat& photo, const Eigen::Vector3f& background, int steps,
                          double rotation_rate, double translation_rate, int coarse_steps) {
  Pose refined = pose;
  if (steps <= 0 || model.size() == 0) return refined;
  cv::Mat target;
  photo.convertTo(target, CV_32FC3, 1.0 / 255);
  RenderSettings settings;
  settings.background = background;
  PoseOptimiser optimiser(rotation_rate, translation_rate);
  ModelGrads unused;
  // Steps [begin, end) against `photo_at` seen through `cam`.
  auto run = [&](const Camera& cam, const cv::Mat& photo_at, int begin, int end) {
    const size_t values = size_t(cam.width) * cam.height * 3;
    RenderGrads grads;
    grads.rgb.resize(values);
    const float* t = photo_at.ptr<float>();
    for (int step = begin; step < end; ++step) {
      const RenderOutput out = render(model, cam, refined, settings);
      // L1: robust to what the training views never saw (the held-out view's uncovered surfaces).
      for (size_t i = 0; i < values; ++i)
        grads.rgb[i] = out.rgb[i] > t[i] ? 1.f / values : (out.rgb[i] < t[i] ? -1.f / values : 0.f);
      unused.reset(model);
      PoseGradient grad;
      render_backward(model, cam, refined, settings, out, grads, unused, &grad);
      optimiser.step(refined, grad);
    }
  };
  const int coarse = std::clamp(coarse_steps, 0, steps);
  if (coarse > 0) {
    const Camera half = camera.scaled(0.5);
    cv::Mat small;
    cv::resize(target, small, cv::Size(half.width, half.height), 0, 0, cv::INTER_AREA);
    run(half, small, 0, coarse);
  }
  run(camera, target, coarse, steps);
  return refined;
}

}  // namespace gslift
