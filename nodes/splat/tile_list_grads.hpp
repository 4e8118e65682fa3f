// What the training losses that walk a render's tile lists again share (line_of_sight_loss.hpp,
// depth_distortion_loss.hpp): where each tile row's blending stopped, and the way from per-entry
// partials (one slot per (Gaussian, tile) pair, raster_state.hpp) to the model's gradients.
#pragma once

#include <cstdint>

#include "nodes/scene/camera.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/splat/raster_state.hpp"
#include "nodes/splat/rasterizer.hpp"

namespace gslift {

// Per tile row, the last contributing list index + 1 of its pixels (row_last), and the largest of
// them, returned: the entries at or past it contributed nowhere in the tile.
uint32_t rows_reached(const TileBlend& blend, uint32_t row_last[kTileSize]);

// Adds k x the slots summed per Gaussian (in tile order) to grads through the projection:
// slots[slot * GeometryMoments::kOutputs + c] as GeometryMoments::reduce writes them (mean2d,
// conic, opacity), and depth_slots[slot], dL/d(camera depth) of the entry, where given. Parallel
// over Gaussians; every Gaussian's sums in a fixed order, so deterministic at any thread count.
void add_slot_grads(const GaussianModel& model, const Camera& camera, const Pose& pose,
                    const RasterState& s, const float* slots, const float* depth_slots, float k,
                    ModelGrads& grads);

}  // namespace gslift
