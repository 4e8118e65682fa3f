#include "nodes/features/contrastive_features.hpp"

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include <tbb/parallel_for.h>

#include "base/random.hpp"
#include "nodes/features/contrastive_loss.hpp"
#include "nodes/splat/adam.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "nodes/splat/render_cache.hpp"
#include "runtime/node.hpp"

namespace gslift {
namespace {

// The per-pixel rows of one view's RenderCache without the contributions below min_weight, and
// without the cache's per-Gaussian transpose: only sampled pixels are ever rendered or
// back-propagated, so the transpose is never needed, and dropping it and the faint tail of each
// blend list cuts the memory several times (measured in contrastive_features.hpp).
struct PixelRows {
  std::vector<uint32_t> offsets;  // pixels + 1
  std::vector<uint32_t> ids;
  std::vector<float> weights;

  PixelRows(const RenderCache& cache, float min_weight) {
    const auto& off = cache.pixel_offsets();
    const auto& all_ids = cache.ids();
    const auto& all_w = cache.weights();
    offsets.reserve(off.size());
    offsets.push_back(0);
    for (size_t p = 0; p + 1 < off.size(); ++p) {
      for (uint32_t e = off[p]; e < off[p + 1]; ++e)
        if (all_w[e] >= min_weight) {
          ids.push_back(all_ids[e]);
          weights.push_back(all_w[e]);
        }
      offsets.push_back(static_cast<uint32_t>(ids.size()));
    }
    ids.shrink_to_fit();
    weights.shrink_to_fit();
  }
  size_t bytes() const {
    return sizeof(uint32_t) * (offsets.size() + ids.size()) + sizeof(float) * weights.size();
  }
};

// One mask of one training view: the pixels inside it (row-major indices) and the mask itself,
// for the outside test.
struct TrainingMask {
  int rows = 0;  // index into view_rows
  cv::Mat1b pixels;
  std::vector<uint32_t> inside;
};

// The sampled pixels of one mask in one iteration (inside first, then outside) and dL/dF there.
struct MaskStep {
  std::vector<uint32_t> pixels;
  std::vector<float> grad;  // pixels x dim
  double loss = 0;
};

void validate(const GaussianModel& model, const ContrastiveOptions& o) {
  if (model.size() == 0) throw InputError("features.contrastive: the model has no Gaussians");
  if (o.iterations < 1 || o.dim < 1 || o.pixels_per_iteration < 1 || !(o.lr > 0) ||
      !(o.lambda >= 0) || !(o.init_std > 0) || !(o.min_weight >= 0))
    throw InputError(
        "features.contrastive: iterations, dim, pixels_per_iteration, lr and init_std must be "
        "positive, lambda and min_weight non-negative");
}

// Renders the features of `pixels` from the cached blend weights (LangOR Eq. 1).
void render_pixels(const PixelRows& rows, const std::vector<float>& features, int dim,
                   const std::vector<uint32_t>& pixels, float* out) {
  const auto& off = rows.offsets;
  const auto& ids = rows.ids;
  const auto& w = rows.weights;
  for (size_t k = 0; k < pixels.size(); ++k) {
    float* o = out + k * dim;
    std::fill(o, o + dim, 0.f);
    for (uint32_t e = off[pixels[k]]; e < off[pixels[k] + 1]; ++e) {
      const float* f = features.data() + size_t(ids[e]) * dim;
      for (int c = 0; c < dim; ++c) o[c] += w[e] * f[c];
    }
  }
}

// Adds W^T grad of the sampled pixels to grad_features (the transposed product, restricted to
// the samples).
void backward_pixels(const PixelRows& rows, const std::vector<uint32_t>& pixels, const float* grad,
                     int dim, std::vector<float>& grad_features) {
  const auto& off = rows.offsets;
  const auto& ids = rows.ids;
  const auto& w = rows.weights;
  for (size_t k = 0; k < pixels.size(); ++k) {
    const float* g = grad + k * dim;
    for (uint32_t e = off[pixels[k]]; e < off[pixels[k] + 1]; ++e) {
      float* d = grad_features.data() + size_t(ids[e]) * dim;
      for (int c = 0; c < dim; ++c) d[c] += w[e] * g[c];
    }
  }
}

// n pixels uniformly inside the mask, then up to n uniformly outside it (rejection sampling over
// the view; none when the mask covers the whole view). Returns the outside count.
int sample_pixels(const TrainingMask& m, int n, RandomStream& rng, std::vector<uint32_t>& pixels) {
  for (int k = 0; k < n; ++k) pixels.push_back(m.inside[rng.below(m.inside.size())]);
  const size_t total = m.pixels.total();
  if (m.inside.size() == total) return 0;
  int out = 0;
  // The expected number of draws is n total / (total - |M|); the cap only guards masks that
  // cover almost everything.
  for (int tries = 0; out < n && tries < 64 * n; ++tries) {
    const size_t p = rng.below(total);
    if (m.pixels.data[p]) continue;
    pixels.push_back(static_cast<uint32_t>(p));
    ++out;
  }
  return out;
}

}  // namespace

ContrastiveResult train_contrastive_features(const GaussianModel& model, const Capture& capture,
                                             const MaskSet& masks, const ContrastiveOptions& o,
                                             const ContrastiveProgress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  validate(model, o);
  const int dim = o.dim;

  // Render view_rows of the training views that have masks, and their non-empty masks.
  std::vector<PixelRows> view_rows;
  std::vector<TrainingMask> training;
  RenderSettings weights_only;
  weights_only.rgb = false;
  weights_only.alpha = true;
  for (const ViewMasks& vm : masks.views) {
    const int vi = capture.find_view(vm.view);
    if (vi < 0)
      throw InputError("features.contrastive: masks name view '" + vm.view +
                       "' that the capture '" + capture.name + "' lacks");
    const View& view = capture.views[vi];
    if (view.held_out) continue;
    const int rows_index = static_cast<int>(view_rows.size());
    for (size_t k = 0; k < vm.masks.size(); ++k) {
      const cv::Mat1b& px = vm.masks[k].pixels;
      if (px.cols != view.camera.width || px.rows != view.camera.height)
        throw InputError(
            "features.contrastive: mask " + std::to_string(k) + " of view '" + vm.view + "' is " +
            std::to_string(px.cols) + "x" + std::to_string(px.rows) + ", the view is " +
            std::to_string(view.camera.width) + "x" + std::to_string(view.camera.height));
      TrainingMask m;
      m.rows = rows_index;
      m.pixels = px.isContinuous() ? px : px.clone();
      for (size_t p = 0; p < m.pixels.total(); ++p)
        if (m.pixels.data[p]) m.inside.push_back(static_cast<uint32_t>(p));
      if (!m.inside.empty()) training.push_back(std::move(m));
    }
    if (!training.empty() && training.back().rows == rows_index)
      view_rows.emplace_back(RenderCache(render(model, view.camera, view.pose, weights_only)),
                             static_cast<float>(o.min_weight));
  }
  if (training.empty())
    throw InputError("features.contrastive: no training view of capture '" + capture.name +
                     "' has a non-empty mask");

  ContrastiveResult result;
  result.masks = static_cast<int>(training.size());
  for (const auto& c : view_rows) result.cache_bytes += c.bytes();

  const size_t n = model.size();
  std::vector<float> features(n * dim);
  {
    RandomStream rng(stream_seed(o.seed, "contrastive.init"));
    for (float& f : features) f = static_cast<float>(rng.normal(0.0, o.init_std));
  }
  std::vector<float> grad(n * dim);
  AdamGroup adam(dim);
  std::vector<MaskStep> steps(training.size());

  for (int it = 0; it < o.iterations; ++it) {
    tbb::parallel_for(size_t(0), training.size(), [&](size_t k) {
      const TrainingMask& m = training[k];
      MaskStep& s = steps[k];
      // One stream per (iteration, mask), numbered row by row.
      RandomStream rng(stream_seed(o.seed, "contrastive.pixels", it * training.size() + k));
      s.pixels.clear();
      const int n_out = sample_pixels(m, o.pixels_per_iteration, rng, s.pixels);
      const int n_in = o.pixels_per_iteration;
      std::vector<float> rendered(s.pixels.size() * dim);
      render_pixels(view_rows[m.rows], features, dim, s.pixels, rendered.data());
      s.grad.resize(rendered.size());
      s.loss =
          mask_contrastive_loss(rendered.data(), n_in, rendered.data() + size_t(n_in) * dim, n_out,
                                dim, o.lambda, s.grad.data(), s.grad.data() + size_t(n_in) * dim);
    });
    // Fixed mask order: the sums do not depend on the thread count.
    double loss = 0;
    std::fill(grad.begin(), grad.end(), 0.f);
    for (size_t k = 0; k < training.size(); ++k) {
      loss += steps[k].loss;
      backward_pixels(view_rows[training[k].rows], steps[k].pixels, steps[k].grad.data(), dim,
                      grad);
    }
    loss /= training.size();
    if (it == 0) result.loss_start = loss;
    result.loss_end = loss;
    adam.step(features.data(), grad.data(), n, static_cast<float>(o.lr));
    if (progress) progress(it, o.iterations);
  }

  result.model = model;
  result.model.feature_dim = dim;
  result.model.features = std::move(features);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace gslift
