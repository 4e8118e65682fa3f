// The depth of a Gaussian along each pixel's ray, for the free-space tests and the
// line-of-sight loss (issue 11). Internal to nodes/splat.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "nodes/scene/camera.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/splat/raster_state.hpp"

namespace gslift {

// Per Gaussian of one view, the depth of its density maximum along a pixel's ray (the
// ray-Gaussian intersection of ray-traced 3DGS, RaDe-GS's per-pixel depth): with the ray
// r = ((u + 0.5 - cx) / fx, (v + 0.5 - cy) / fy, 1), the camera-space mean m and precision
// P = Sigma^-1, t*(r) = (r . P m) / (r . P r) is that point's camera depth. A flat Gaussian's ray
// depth follows its plane across its footprint: a surface the view sees at a slant is tested
// where it is at each pixel, not at its centre's depth, which differs from it by the footprint's
// extent times the slant. Clamped to the centre's depth +- 3 x the largest scale (a ray in the
// plane of a disc has no well-defined maximum) and to +- kMaxRelative of it (so that the
// line-of-sight loss's pass still ends where the centres pass every cut). The EntryDepth of
// blend_tile's cut.
class RayDepths {
 public:
  // Gaussians that `projections` (the view's forward pass) culled get no coefficients.
  RayDepths(const GaussianModel& model, const Camera& camera, const Pose& pose,
            const std::vector<ProjectedGaussian>& projections);
  static constexpr float kMaxRelative = 0.1f;
  // The nearest depth the Gaussian takes at any pixel.
  float nearest(uint32_t id) const { return nearest_[id]; }
  // The nearest depth any Gaussian whose centre lies no nearer than this one's can take
  // (blend_tile's EntryDepth::sorted_bound): (1 - kMaxRelative) x its centre depth.
  float sorted_bound(uint32_t id) const { return sorted_bound_[id]; }
  // z[x] = the ray depth of Gaussian id at pixel (x0 + x, y), x < kLanes.
  void prefetch(uint32_t id) const {
    const float* c = &coeffs_[size_t(id) * kCoeffs];
    __builtin_prefetch(c);
    __builtin_prefetch(c + kCoeffs - 1);
    __builtin_prefetch(&nearest_[id]);
    __builtin_prefetch(&sorted_bound_[id]);
  }
  void row(uint32_t id, int y, int x0, float* z) const {
    const float* c = &coeffs_[size_t(id) * kCoeffs];
    const float ry = ray_y_[size_t(y)];
    const float* rx = &ray_x_[size_t(x0)];
    const float num0 = c[1] * ry + c[2], den0 = (c[5] * ry + c[7]) * ry + c[8];
    const float den1 = c[4] * ry + c[6];
    for (int x = 0; x < kLanes; ++x) {
      const float t = (c[0] * rx[x] + num0) / ((c[3] * rx[x] + den1) * rx[x] + den0);
      z[x] = std::min(std::max(t, c[9]), c[10]);
    }
  }

 private:
  static constexpr int kCoeffs = 11;  // P m (3), r . P r's six coefficients, the clamp (2)
  std::vector<float> coeffs_;
  // The rays' (x + 0.5 - cx) / fx per image column and (y + 0.5 - cy) / fy per row, over whole
  // tiles: a division per lane that row() did again for every entry row it was called for.
  std::vector<float> ray_x_, ray_y_;
  // coeffs_[9] of each Gaussian again, contiguous: the passes with a cut test it for every list
  // entry they meet, most of which they skip, and a 44-byte stride made that a cache miss each.
  // Likewise the bound from the centre depth, which was read from the 52-byte projections.
  std::vector<float> nearest_, sorted_bound_;
};

// Calls f(depth) with the depths of the entries of render state s (of `model` in this view) that
// the free-space tests and the line-of-sight loss compare with the prior: RayDepths with
// ray_depth, else CentreDepth. Both are blend_tile's EntryDepth.
template <class F>
void with_entry_depths(bool ray_depth, const GaussianModel& model, const Camera& camera,
                       const Pose& pose, const RasterState& s, F&& f) {
  if (ray_depth)
    f(RayDepths(model, camera, pose, s.projections));
  else
    f(CentreDepth{s.projections});
}

}  // namespace gslift
