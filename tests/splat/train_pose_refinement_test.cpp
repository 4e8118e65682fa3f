// Pose refinement (pose_correction.hpp): a held-out view registered to its photo against a known
// model, and a training view's pose corrected while the model trains.
#include <cmath>

#include <Eigen/Geometry>

#include "nodes/splat/pose_correction.hpp"
#include "nodes/splat/reconstruct.hpp"
#include "nodes/splat/training_targets.hpp"
#include "tests/splat/train_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

// The pose moved by `degrees` about a fixed tilted axis and `shift` along another, in camera space.
Pose disturbed(const Pose& pose, double degrees, double shift) {
  PoseGradient delta;
  delta.head<3>() = Eigen::Vector3d(0.3, -0.8, 0.5).normalized() * degrees * M_PI / 180;
  delta.tail<3>() = Eigen::Vector3d(0.6, 0.2, -0.77).normalized() * shift;
  return corrected_pose(pose, delta);
}

}  // namespace

TEST_CASE("a correction of (w, dt) moves the pose by |w| and the centre as dt says") {
  const Capture capture = test::rendered_capture();
  const Pose& pose = capture.views[0].pose;
  const Pose moved = disturbed(pose, 0.8, 0.05);
  const PoseChange change = pose_change(pose, moved);
  CHECK(change.degrees == Approx(0.8).epsilon(1e-9));
  // centre' = -R'^T t' = centre - R'^T dt: a pure translation moves it by |dt|; a rotation about
  // the camera centre does not move it.
  CHECK(pose_change(pose, disturbed(pose, 0, 0.05)).centre == Approx(0.05).epsilon(1e-9));
  CHECK(pose_change(pose, disturbed(pose, 0.8, 0)).centre < 1e-12);
}

TEST_CASE("a held-out view's pose registers to its photo against the model") {
  const GaussianModel truth = test::ground_truth_scene();
  const Capture capture = test::rendered_capture();
  const View& view = capture.views[4];
  const Pose start = disturbed(view.pose, 1.0, 0.04);
  const PoseChange before = pose_change(view.pose, start);
  const Pose refined = refine_pose_to_photo(truth, view.camera, start, load_view_rgb(view),
                                            Eigen::Vector3f::Zero(), 150, 2e-3, 1e-3);
  const PoseChange after = pose_change(view.pose, refined);
  INFO("rotation error " << before.degrees << " -> " << after.degrees << " deg, centre "
                         << before.centre << " -> " << after.centre);
  CHECK(after.degrees < 0.25 * before.degrees);
  CHECK(after.centre < 0.25 * before.centre);
  // The first half of the steps at half resolution (a quarter of the pixels) registers as well,
  // on its own path (its pose is not the full-resolution one).
  const Pose coarse = refine_pose_to_photo(truth, view.camera, start, load_view_rgb(view),
                                           Eigen::Vector3f::Zero(), 150, 2e-3, 1e-3, 75);
  const PoseChange coarse_after = pose_change(view.pose, coarse);
  INFO("coarse to fine: " << coarse_after.degrees << " deg, centre " << coarse_after.centre);
  CHECK(coarse_after.degrees < 0.25 * before.degrees);
  CHECK(coarse_after.centre < 0.25 * before.centre);
  CHECK(pose_change(refined, coarse).degrees > 1e-6);
  // No steps: the written pose comes back untouched.
  const Pose kept = refine_pose_to_photo(truth, view.camera, start, load_view_rgb(view),
                                         Eigen::Vector3f::Zero(), 0, 2e-3, 1e-3);
  CHECK(kept.R == start.R);
  CHECK(kept.t == start.t);
}

TEST_CASE("refine_poses corrects a training view's pose while the model trains", "[long]") {
  const Capture truth = test::rendered_capture();
  Capture capture = truth;
  capture.views[1].pose = disturbed(truth.views[1].pose, 1.0, 0.04);
  ReconstructOptions o;
  o.iterations = 300;
  o.init.pixel_stride = 1;
  o.init.footprint_factor = 2;
  o.seed = 5;
  const ReconstructResult fixed = reconstruct(capture, o);
  o.poses.refine = true;
  o.poses.rotation_lr = 1e-3;
  o.poses.translation_lr = 5e-4;
  const ReconstructResult refined = reconstruct(capture, o);
  REQUIRE(refined.poses.size() == capture.views.size());
  const PoseChange before = pose_change(truth.views[1].pose, capture.views[1].pose);
  const PoseChange after = pose_change(truth.views[1].pose, refined.poses[1]);
  INFO("view 1: rotation error " << before.degrees << " -> " << after.degrees << " deg, centre "
                                 << before.centre << " -> " << after.centre << "; train PSNR "
                                 << fixed.train_psnr << " -> " << refined.train_psnr);
  CHECK(after.degrees < 0.5 * before.degrees);
  CHECK(after.centre < 0.75 * before.centre);
  CHECK(refined.train_psnr > fixed.train_psnr + 1);
  // Without refinement every pose comes back as written.
  for (size_t v = 0; v < capture.views.size(); ++v) {
    CHECK(fixed.poses[v].R == capture.views[v].pose.R);
    CHECK(fixed.poses[v].t == capture.views[v].pose.t);
  }
}
