// Differentiable CPU rasterizer for 3D Gaussian Splatting (3DGS, Kerbl et al. 2023).
// Forward: EWA projection, 16x16 tile binning, per-tile depth sort, front-to-back alpha blending.
// One pass renders any selection of RGB, expected depth, normal, accumulated alpha and the model's
// D feature channels. Backward: exact gradients of every rendered channel with respect to every
// GaussianModel parameter. Both passes run in parallel over tiles (TBB) and give bitwise identical
// results at any thread count: each tile writes only its own pixels, and per-Gaussian gradient
// contributions are summed in a fixed order (tile index, then depth order within the tile).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "base/uninit_vector.hpp"
#include "nodes/scene/camera.hpp"
#include "nodes/scene/gaussian_model.hpp"

namespace gslift {

// Which channels one pass renders, and how.
struct RenderSettings {
  bool rgb = true;        // SH colour for the view direction, +0.5 offset, clamped at 0 (3DGS)
  bool depth = false;     // expected camera-space depth sum_i w_i z_i
  bool normal = false;    // sum_i w_i n_i, n_i the world-space shortest axis facing the camera
  bool alpha = false;     // accumulated opacity sum_i w_i = 1 - T_final
  bool features = false;  // sum_i w_i f_i over the model's feature_dim channels (LangOR Eq. 1)
  // With features: null renders them at every pixel; otherwise they are exact at least at these
  // pixels (row-major indices) and may be 0 elsewhere, which skips most of their cost when a loss
  // reads a few sampled pixels (a FeatureObjective, feature_objective.hpp).
  std::shared_ptr<const std::vector<uint32_t>> feature_pixels;
  // Divide depth by the accumulated alpha (pixels with alpha < 1e-6 get 0); otherwise depth is the
  // unnormalised sum, which is what a depth loss against a dense prior usually wants.
  bool normalize_depth = false;
  float near = 0.01f;  // cull Gaussians with camera z below this (near plane)
  // Contributions with alpha below this are skipped (3DGS: 1/255). The skip makes the image a
  // discontinuous function of the parameters; finite-difference gradient checks set it to 0.
  float min_alpha = 1.f / 255.f;
  // SH degree evaluated (0..model.sh_degree); -1 = the model's degree. Training raises it
  // progressively as in 3DGS; higher coefficients are ignored and get zero gradient.
  int sh_degree = -1;
  Eigen::Vector3f background{0.f, 0.f, 0.f};  // RGB only: C += T_final * background
};

// Per-view state the forward pass keeps for the backward pass (projected Gaussians, tile lists,
// final transmittance and last contributor per pixel). Opaque: defined in raster_state.hpp.
struct RasterState;

// Rendered channels, row-major images; a channel not requested is empty.
struct RenderOutput {
  int width = 0;
  int height = 0;
  int feature_dim = 0;
  std::vector<float> rgb;        // H x W x 3
  std::vector<float> depth;      // H x W
  std::vector<float> normal;     // H x W x 3, WORLD space, not normalised (a blend of unit vectors)
  std::vector<float> alpha;      // H x W
  UninitVector<float> features;  // H x W x feature_dim; not zeroed before the tiles write it
  // Screen-space radius in pixels per Gaussian (N), ceil(3 sqrt(lambda_max)) of the 2D covariance;
  // 0 = not drawn: culled, off-screen, or too faint to reach min_alpha anywhere. For densification
  // ("prune Gaussians larger than r pixels") and visibility statistics.
  std::vector<int32_t> radii;
  std::shared_ptr<const RasterState> state;  // needed by render_backward
};

// dL/d(rendered channel), same layouts as RenderOutput; an empty vector means zero gradient.
struct RenderGrads {
  std::vector<float> rgb, depth, normal, alpha, features;
};

// Gradients with respect to the model's stored (pre-activation) parameters, same layouts as
// GaussianModel. render_backward ADDS into these, so one instance accumulates over views.
struct ModelGrads {
  std::vector<float> means;           // N x 3
  std::vector<float> log_scales;      // N x 3
  std::vector<float> quats;           // N x 4 (gradient wrt the unnormalised quaternion)
  std::vector<float> opacity_logits;  // N
  std::vector<float> sh;              // N x K x 3
  std::vector<float> features;        // N x feature_dim
  // Densification statistics (3DGS): per Gaussian, the sum over views of the norm of dL/d(2D mean)
  // in NDC units (pixel gradient times (W/2, H/2), so the 3DGS threshold 2e-4 applies), and the
  // number of views in which it was visible (radius > 0). Mean gradient = mean2d_abs / visible.
  std::vector<float> mean2d_abs;  // N
  std::vector<int32_t> visible;   // N

  // Sizes every array for the model and sets it to zero.
  void reset(const GaussianModel& model);
};

// dL/d of a view's pose correction (pose_correction.hpp): rotation w (0-2), translation dt (3-5),
// both in camera space. Exact for every rendered channel (the projected means and covariances
// and the SH view direction).
using PoseGradient = Eigen::Matrix<double, 6, 1>;

// Renders the selected channels of the model seen by camera/pose. Throws InputError when the
// model's arrays are inconsistent in size or the camera has no pixels.
RenderOutput render(const GaussianModel& model, const Camera& camera, const Pose& pose,
                    const RenderSettings& settings);

// Backpropagates grads (dL/d each rendered channel) through the forward pass `forward`, which
// must come from render() with the same model, camera, pose and settings. Adds into `accumulate`
// (reset() it first, or sizes are checked and an InputError is thrown). With pose_grad, also
// sets it to dL/d of the view's pose correction.
void render_backward(const GaussianModel& model, const Camera& camera, const Pose& pose,
                     const RenderSettings& settings, const RenderOutput& forward,
                     const RenderGrads& grads, ModelGrads& accumulate,
                     PoseGradient* pose_grad = nullptr);

}  // namespace gslift
