// Camera poses refined by the reconstruction's own photometric gradient: a capture's written poses
// are a calibration's or an SfM's, a few tenths of a degree and centimetres off on a real rig
// (the embedded OR's `hard` preset writes them 0.5 degrees and 2 cm off). Each training view's
// pose is optimised jointly with the Gaussians, as gsplat's `pose_opt` and nerfstudio's camera
// optimiser do (docs/references.md), and each held-out view's pose against its photo with the
// model fixed afterwards, as a held-out view's pose is registered by SfM from its photo too.
//
// A correction is a small rotation w (axis-angle) and translation dt applied in the camera's
// frame after the pose: x_cam = exp([w]x) (R x + t) + dt. The rasterizer's backward pass gives
// dL/d(w, dt) at w = dt = 0 (PoseGradient), so each update is applied to the current pose and
// Adam's moments live in the camera's frame.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "nodes/scene/camera.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/splat/adam.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "param/param_table.hpp"

namespace gslift {

// splat.reconstruct's pose refinement (its params refine_poses, pose_rotation_lr, ...).
struct PoseRefinementOptions {
  bool refine = false;
  double rotation_lr = 2e-4;       // Adam rate of the rotation, radians per step
  double translation_lr = 1.5e-4;  // Adam rate of the translation, scene extents per step
  int held_out_steps = 120;        // steps per held-out view against its photo; 0 = keep its pose
  // The first fraction of held_out_steps at half resolution (a quarter of the pixels): the photo's
  // coarse shift needs no fine detail (bench/splat_recon/README.md, "Poses refined with the
  // scene").
  double held_out_coarse = 0;
};

// The pose moved by the correction `delta` (w in 0-2, dt in 3-5; see above).
Pose corrected_pose(const Pose& pose, const PoseGradient& delta);

// The size of the correction from `written` to `refined`: rotation in degrees, camera centre
// displacement in the capture's units.
struct PoseChange {
  double degrees = 0;
  double centre = 0;
};
PoseChange pose_change(const Pose& written, const Pose& refined);

// Adam over one view's pose correction (AdamGroup with one row of 6).
class PoseOptimiser {
 public:
  // translation_rate in the capture's units per step (the option's rate times the extent).
  PoseOptimiser(double rotation_rate, double translation_rate, AdamSettings settings = {});
  // One update of `pose` against dL/d(w, dt) at `pose`.
  void step(Pose& pose, const PoseGradient& grad);

 private:
  AdamGroup adam_;
  float rates_[6];
};

// The held-out view's pose registered to its photo (CV_8UC3 RGB of the camera's size) with the
// model fixed: `steps` Adam updates of the L1 photometric error of the RGB render over
// `background`, the first coarse_steps of them at half resolution (Camera::scaled, the photo
// area-averaged). Returns the refined pose; the written one when steps is 0.
Pose refine_pose_to_photo(const GaussianModel& model, const Camera& camera, const Pose& pose,
                          const cv::Mat& photo, const Eigen::Vector3f& background, int steps,
                          double rotation_rate, double translation_rate, int coarse_steps = 0);

}  // namespace gslift
