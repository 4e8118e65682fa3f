// A 0/1 per-Gaussian selection rendered as a 2D mask in one view, fast enough for an interactive
// prompt (SAGA, paper 001 §4.4: segmentation "in milliseconds"; its render.py renders the 0/1
// mask as a colour and thresholds it at 0.5). The mask is the accumulated alpha of the selected
// Gaussians alone, A(p) = sum_{i selected} w_i(p), compared with a threshold, where w_i(p) are the
// frozen blend weights of one forward pass (nodes/splat/render_cache.hpp).
//
// The render cache stores each pixel's (Gaussian, weight) pairs; a selection's sparse product
// reads every pair of the view (about 12M on the embedded OR) for one bit of the answer. Here
// the same pairs are regrouped once per view, per 16x16 tile, by Gaussian: each tile keeps its
// contributing Gaussians and, for each, the pixels it covers with their weights. A mask then
// scans the tiles' Gaussian lists (a tenth of the pairs), skips every Gaussian that is not
// selected, and adds the weights of the selected ones into a 256-float tile accumulator: the work
// is the tile lists plus the pairs of the selection, not the pairs of the view.
//
// A(p) sums the same weights as the full product in another order (by Gaussian id instead of
// front to back), so it equals the full render up to float rounding (a few 1e-7 relative); a
// pixel's answer can only differ from the full render's when its A(p) lies that close to the
// threshold (tests/inference/selection_mask_test.cpp bounds it). Deterministic at any thread
// count: each tile's sums run in a fixed order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "nodes/scene/camera.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/splat/render_cache.hpp"

namespace gslift {

// The blend weights alpha_i T_i of one render of `model` from (camera, pose).
RenderCache render_weights(const GaussianModel& model, const Camera& camera, const Pose& pose);

class SelectionMasker {
 public:
  explicit SelectionMasker(const RenderCache& cache);
  // Renders the blend weights of `model` from the camera (one forward pass, weights only).
  SelectionMasker(const GaussianModel& model, const Camera& camera, const Pose& pose);

  int width() const { return width_; }
  int height() const { return height_; }
  size_t gaussian_count() const { return gaussians_; }
  size_t bytes() const;  // memory held

  // A(p): the accumulated alpha of the selected Gaussians (one flag per Gaussian).
  cv::Mat1f coverage(const std::vector<uint8_t>& selected) const;
  // 255 where A(p) >= threshold, else 0. Throws InputError when `selected` does not have one flag
  // per Gaussian.
  cv::Mat1b mask(const std::vector<uint8_t>& selected, float threshold) const;

 private:
  template <class Write>
  void accumulate(const std::vector<uint8_t>& selected, Write&& write) const;

  int width_ = 0, height_ = 0, tiles_x_ = 0, tiles_y_ = 0;
  size_t gaussians_ = 0;
  // Tile t owns entries [tile_offsets_[t], tile_offsets_[t+1]): its Gaussians (ascending id);
  // entry e owns pairs [entry_offsets_[e], entry_offsets_[e+1]): the pixels it covers (y * 16 + x
  // inside the tile, ascending) and their weights.
  std::vector<uint32_t> tile_offsets_;
  std::vector<uint32_t> entry_ids_;
  std::vector<uint32_t> entry_offsets_;
  std::vector<uint8_t> pair_pixels_;
  std::vector<float> pair_weights_;
};

}  // namespace gslift
