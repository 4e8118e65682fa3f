#include "nodes/splat/tile_list_grads.hpp"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "nodes/splat/projection.hpp"

namespace gslift {

uint32_t rows_reached(const TileBlend& blend, uint32_t row_last[kTileSize]) {
  uint32_t reached = 0;
  for (int row = 0; row < kTileSize; ++row) {
    row_last[row] =
        *std::max_element(blend.last + row * kTileSize, blend.last + (row + 1) * kTileSize);
    reached = std::max(reached, row_last[row]);
  }
  return reached;
}

void add_slot_grads(const GaussianModel& model, const Camera& camera, const Pose& pose,
                    const RasterState& s, const float* slots, const float* depth_slots, float k,
                    ModelGrads& grads) {
  constexpr int kPartials = GeometryMoments::kOutputs;
  const ViewTransform view(camera, pose);
  tbb::parallel_for(size_t(0), model.size(), [&](size_t i) {
    float sum[kPartials] = {}, depth = 0;
    for (uint32_t slot = s.slot_offsets[i]; slot < s.slot_offsets[i + 1]; ++slot) {
      for (int c = 0; c < kPartials; ++c) sum[c] += slots[size_t(slot) * kPartials + c];
      if (depth_slots) depth += depth_slots[slot];
    }
    if (depth == 0.f && std::all_of(sum, sum + kPartials, [](float v) { return v == 0.f; })) return;
    ProjectionGrads pg;
    pg.mean2d = k * Eigen::Vector2f(sum[0], sum[1]);
    pg.conic = k * Eigen::Vector3f(sum[2], sum[3], sum[4]);
    pg.depth = k * depth;
    project_gaussian_backward(view, &model.means[i * 3], &model.log_scales[i * 3],
                              &model.quats[i * 4], pg, &grads.means[i * 3],
                              &grads.log_scales[i * 3], &grads.quats[i * 4]);
    const float o = 1.f / (1.f + std::exp(-model.opacity_logits[i]));
    grads.opacity_logits[i] += k * sum[5] * o * (1 - o);
  });
}

}  // namespace gslift
