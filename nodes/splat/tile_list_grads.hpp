// What the training losses that walk a render's tile lists again share (line_of_sight_loss.hpp):
// where each tile row's blending stopped, and the way from per-entry partials (one slot per
// (Gaussian, tile) pair, raster_state.hpp) to the model's gradients.
#pragma once

#include <algorithm>
#include <cstdint>

#include "nodes/scene/camera.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/splat/raster_state.hpp"
#include "nodes/splat/rasterizer.hpp"

namespace gslift {

// Per tile row, the last contributing list index + 1 of its pixels (row_last), and the largest of
// them, returned: the entries at or past it contributed nowhere in the tile.
uint32_t rows_reached(const TileBlend& blend, uint32_t row_last[kTileSize]);

// The gradient pass of such a loss over tile t, after blend_tile wrote `front`: every entry j of
// the list in blending order, each over the rows of its rectangle where it can have contributed
// (j < that row's last), with blend_row's Gaussian values and alphas for the row's kLanes pixels
// from the tile's left edge. on_row(j, e, rect, y, at, gaussian, alpha, moments) adds that row's
// lanes to the entry's moments (at: the row's first tile pixel); the moments are reduced into
// slots[e.slot * GeometryMoments::kOutputs ...], zero for an entry that contributed nowhere; then
// on_entry(j, e) runs, for every entry. Rows where skip_row(e, row) (row: the tile row) is true
// are left out: the caller knows that none of their lanes would add anything.
template <class SkipRow, class OnRow, class OnEntry>
void walk_contributions(const RasterState& s, int t, const TileBlend& front, float* slots,
                        SkipRow&& skip_row, OnRow&& on_row, OnEntry&& on_entry) {
  const TileGaussian* list = s.tile_gaussians.data() + s.tile_offsets[t];
  const uint32_t count = s.tile_offsets[t + 1] - s.tile_offsets[t];
  const PixelRect tile = tile_pixels(s, t);
  uint32_t row_last[kTileSize];
  const uint32_t reached = rows_reached(front, row_last);
  alignas(64) float gaussian[kLanes], alpha[kLanes];
  for (uint32_t j = 0; j < count; ++j) {
    const TileGaussian& e = list[j];
    float* slot = &slots[size_t(e.slot) * GeometryMoments::kOutputs];
    const PixelRect rect = clip(e, tile);
    if (j >= reached || rect.y1 <= rect.y0) {
      std::fill_n(slot, GeometryMoments::kOutputs, 0.f);
    } else {
      GeometryMoments moments;
      for (int y = rect.y0; y < rect.y1; ++y) {
        if (j >= row_last[y - tile.y0] || skip_row(e, y - tile.y0)) continue;
        blend_row(e, y, tile.x0, tile.x0 + kLanes, s.min_alpha, gaussian, alpha);
        on_row(j, e, rect, y, (y - tile.y0) * kTileSize, gaussian, alpha, moments);
      }
      moments.reduce(e, slot);
    }
    on_entry(j, e);
  }
}

// Adds k x the slots summed per Gaussian (in tile order) to grads through the projection:
// slots[slot * GeometryMoments::kOutputs + c] as GeometryMoments::reduce writes them (mean2d,
// conic, opacity), and depth_slots[slot], dL/d(camera depth) of the entry, where given. Parallel
// over Gaussians; every Gaussian's sums in a fixed order, so deterministic at any thread count.
void add_slot_grads(const GaussianModel& model, const Camera& camera, const Pose& pose,
                    const RasterState& s, const float* slots, const float* depth_slots, float k,
                    ModelGrads& grads);

}  // namespace gslift
