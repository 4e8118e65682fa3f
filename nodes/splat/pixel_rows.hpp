// Rendering at sampled pixels only. Training on frozen geometry (LangOR's contrastive features,
// Proto-SaGa's view classifiers, SAGA's correspondence loss) renders a few hundred sampled pixels
// per step, not whole views: the rows S of the sparse product F = W A (LangOR Eq. 1) and its
// adjoint dL/dA += W_S^T dL/dF_S. The per-pixel rows are CSR: pixel p owns
// [offsets[p], offsets[p+1]) of ids / weights, front to back.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace gslift {

struct RenderOutput;

// The CSR arrays of some view's per-pixel blend weights, borrowed.
struct PixelRowsView {
  const uint32_t* offsets = nullptr;
  const uint32_t* ids = nullptr;
  const float* weights = nullptr;
};

// out (pixels.size() x channels, row-major) = the rows `pixels` of W times attributes
// (N x channels, row-major).
void render_sampled_pixels(const PixelRowsView& rows, const float* attributes, int channels,
                           const std::vector<uint32_t>& pixels, float* out);
// The adjoint: grad_attributes (N x channels) += W_S^T grad (pixels.size() x channels), summed in
// sample order (deterministic); only the rows of the ids in [id_begin, id_end), so that tasks over
// disjoint id ranges add in parallel, each row's sum in the same order as one pass over all.
void backward_sampled_pixels(const PixelRowsView& rows, const std::vector<uint32_t>& pixels,
                             const float* grad, int channels, float* grad_attributes,
                             uint32_t id_begin = 0,
                             uint32_t id_end = std::numeric_limits<uint32_t>::max());

// A view's per-pixel blend weights without the pairs below `min_weight` and without a render
// cache's tile lists and per-Gaussian transpose, which sampled-pixel training never needs:
// dropping them and the faint tail of each blend list cuts the memory several times (measured for
// LangOR's features in nodes/features/contrastive_features.hpp).
class PixelRows {
 public:
  // From a forward render's raster state, in one blending pass, without building a RenderCache:
  // its pixel rows' pairs at or above min_weight in the same front-to-back order. Deterministic at
  // any thread count. Throws InputError when forward has no raster state.
  explicit PixelRows(const RenderOutput& forward, float min_weight = 0.f);

  size_t pixel_count() const { return offsets_.size() - 1; }
  size_t entries() const { return ids_.size(); }
  size_t bytes() const {
    return sizeof(uint32_t) * (offsets_.size() + ids_.size()) + sizeof(float) * weights_.size();
  }
  PixelRowsView view() const { return {offsets_.data(), ids_.data(), weights_.data()}; }

  void render(const float* attributes, int channels, const std::vector<uint32_t>& pixels,
              float* out) const {
    render_sampled_pixels(view(), attributes, channels, pixels, out);
  }
  void backward(const std::vector<uint32_t>& pixels, const float* grad, int channels,
                float* grad_attributes, uint32_t id_begin = 0,
                uint32_t id_end = std::numeric_limits<uint32_t>::max()) const {
    backward_sampled_pixels(view(), pixels, grad, channels, grad_attributes, id_begin, id_end);
  }

 private:
  std::vector<uint32_t> offsets_;  // pixels + 1
  std::vector<uint32_t> ids_;
  std::vector<float> weights_;
};

}  // namespace gslift
