// What the training losses that walk a render's tile lists again share (line_of_sight_loss.hpp):
// where each tile row's blending stopped, and the way from per-entry partials (one slot per
// (Gaussian, tile) pair, raster_state.hpp) to the model's gradients.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include "nodes/scene/camera.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/splat/raster_state.hpp"
#include "nodes/splat/rasterizer.hpp"

namespace gslift {

// Per tile row, the last contributing list index + 1 of its pixels (row_last), and the largest of
// them, returned: the entries at or past it contributed nowhere in the tile.
uint32_t rows_reached(const TileBlend& blend, uint32_t row_last[kTileSize]);

// The entry rows blend_tile blended in one tile, in its order (entry by entry, each row by row),
// with their RowLanes copied: the gradient pass reads them back instead of computing blend_row's
// exp chain and the entries' depths again. Reused from tile to tile (clear keeps the memory).
class BlendedRows {
 public:
  void clear() {
    entries_.clear();
    ats_.clear();
    lanes_.clear();
  }
  // The row of entry j at tile pixel `at` (its first), lanes.depth given.
  void add(uint32_t j, int at, const RowLanes& lanes) {
    entries_.push_back(j);
    ats_.push_back(at);
    const size_t end = lanes_.size();
    lanes_.resize(end + 3 * kLanes);
    // Fixed-size copies, which compile to vector moves (an insert of each was a memmove call).
    std::memcpy(&lanes_[end], lanes.gaussian, kLanes * sizeof(float));
    std::memcpy(&lanes_[end + kLanes], lanes.alpha, kLanes * sizeof(float));
    std::memcpy(&lanes_[end + 2 * kLanes], lanes.depth, kLanes * sizeof(float));
  }
  size_t size() const { return entries_.size(); }
  uint32_t entry(size_t i) const { return entries_[i]; }
  int at(size_t i) const { return ats_[i]; }
  RowLanes lanes(size_t i) const {
    const float* v = &lanes_[i * 3 * kLanes];
    return {v, v + kLanes, v + 2 * kLanes};
  }

 private:
  std::vector<uint32_t> entries_;
  std::vector<int> ats_;
  UninitVector<float> lanes_;
};

// The gradient pass of such a loss over tile t, after blend_tile wrote `front` and `rows` holds
// the rows it blended: every entry j of the list in blending order, each over its blended rows
// where it can have contributed (j < that row's last). on_row(j, e, rect, y, at, lanes, moments)
// adds that row's lanes to the entry's moments (rect: the entry's pixels in the tile; at: the
// row's first tile pixel); the moments are reduced into slots[e.slot * GeometryMoments::kOutputs
// ...], zero for an entry that contributed nowhere. A row blend_tile skipped has no lane that could
// add anything: the moments' sums are the same bit for bit as over every row of the entry's
// rectangle.
template <class OnRow>
void walk_contributions(const RasterState& s, int t, const TileBlend& front,
                        const BlendedRows& rows, float* slots, OnRow&& on_row) {
  const TileGaussian* list = s.tile_gaussians.data() + s.tile_offsets[t];
  const uint32_t count = s.tile_offsets[t + 1] - s.tile_offsets[t];
  const PixelRect tile = tile_pixels(s, t);
  uint32_t row_last[kTileSize];
  const uint32_t reached = rows_reached(front, row_last);
  size_t next = 0;  // the first of `rows` not yet walked
  for (uint32_t j = 0; j < count; ++j) {
    const TileGaussian& e = list[j];
    float* slot = &slots[size_t(e.slot) * GeometryMoments::kOutputs];
    const size_t first = next;
    while (next < rows.size() && rows.entry(next) == j) ++next;
    const PixelRect rect = clip(e, tile);
    if (j >= reached || rect.y1 <= rect.y0) {
      std::fill_n(slot, GeometryMoments::kOutputs, 0.f);
      continue;
    }
    GeometryMoments moments;
    for (size_t i = first; i < next; ++i) {
      const int row = rows.at(i) / kTileSize;
      if (j < row_last[row]) on_row(j, e, rect, tile.y0 + row, rows.at(i), rows.lanes(i), moments);
    }
    moments.reduce(e, slot);
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
