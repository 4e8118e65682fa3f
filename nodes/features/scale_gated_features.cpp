#include "nodes/features/scale_gated_features.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <numeric>

#include <tbb/parallel_for.h>

#include "base/errors.hpp"
#include "base/random.hpp"
#include "nodes/features/correspondence_loss.hpp"
#include "nodes/features/feature_smoothing.hpp"
#include "nodes/features/mask_scales.hpp"
#include "nodes/features/pixel_feature_training.hpp"
#include "nodes/features/scale_gated_loss.hpp"
#include "nodes/splat/rasterizer.hpp"

namespace gslift {
namespace {

// One training view: mask membership in scale order (bit i = the i-th largest mask), the masks'
// scales in that order and their areas.
struct GatedView {
  MaskedPixels masks;  // membership bits in scale order
  std::vector<float> scales;
  std::vector<float> areas;
};

// x / |x| per row, the norms kept (rows of norm 0 stay 0).
void normalise(const float* in, size_t n, int dim, float* out, float* norms) {
  tbb::parallel_for(size_t(0), n, [&](size_t g) {
    double s = 0;
    for (int c = 0; c < dim; ++c) s += double(in[g * dim + c]) * in[g * dim + c];
    norms[g] = static_cast<float>(std::sqrt(s));
    const float inv = norms[g] > 1e-12f ? 1.f / norms[g] : 0.f;
    for (int c = 0; c < dim; ++c) out[g * dim + c] = in[g * dim + c] * inv;
  });
}

// In place: grad wrt x / |x| -> grad wrt x.
void through_normalise(const float* unit, const float* norms, size_t n, int dim, float* grad) {
  tbb::parallel_for(size_t(0), n, [&](size_t g) {
    if (norms[g] <= 1e-12f) {
      std::fill(grad + g * dim, grad + (g + 1) * dim, 0.f);
      return;
    }
    float along = 0;
    for (int c = 0; c < dim; ++c) along += grad[g * dim + c] * unit[g * dim + c];
    for (int c = 0; c < dim; ++c)
      grad[g * dim + c] = (grad[g * dim + c] - along * unit[g * dim + c]) / norms[g];
  });
}

}  // namespace

QuantileMap::QuantileMap(std::vector<float> v) {
  if (v.empty()) throw InputError("features.correspondence: no mask scales to normalise");
  std::sort(v.begin(), v.end());
  const size_t nq = std::min<size_t>(1000, v.size());
  for (size_t i = 0; i < nq; ++i) {
    const double r = nq == 1 ? 0.0 : double(i) / double(nq - 1);
    // numpy percentile, linear interpolation.
    const double at = r * double(v.size() - 1);
    const size_t lo = static_cast<size_t>(std::floor(at));
    const size_t hi = std::min(lo + 1, v.size() - 1);
    quantiles_.push_back(v[lo] + (at - lo) * (double(v[hi]) - v[lo]));
    references_.push_back(r);
  }
}

float QuantileMap::operator()(float x) const {
  // np.interp(x, xp, fp) with xp ascending (ties: the last of equal xp on the way up).
  auto interp = [](double x, const std::vector<double>& xp, const std::vector<double>& fp) {
    if (x <= xp.front()) return fp.front();
    if (x >= xp.back()) return fp.back();
    const size_t j = std::upper_bound(xp.begin(), xp.end(), x) - xp.begin();
    const double t = (x - xp[j - 1]) / (xp[j] - xp[j - 1]);
    return fp[j - 1] + t * (fp[j] - fp[j - 1]);
  };
  std::vector<double> nq(quantiles_.rbegin(), quantiles_.rend()),
      nr(references_.rbegin(), references_.rend());
  for (double& q : nq) q = -q;
  for (double& r : nr) r = -r;
  const double y = 0.5 * (interp(x, quantiles_, references_) - interp(-x, nq, nr));
  return static_cast<float>(std::clamp(y, 0.0, 1.0));
}

CorrespondenceResult train_scale_gated_features(const GaussianModel& model, const Capture& capture,
                                                const MaskSet& masks,
                                                const CorrespondenceOptions& o,
                                                const TrainingProgress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  if (model.size() == 0) throw InputError("features.correspondence: the model has no Gaussians");
  CorrespondenceResult result;
  std::vector<PixelRows> rows;
  std::vector<GatedView> views;
  std::vector<float> all_scales;
  for (const MaskView& mv : training_mask_views(capture, masks)) {
    const ViewMasks& vm = masks.views[mv.mask_view];
    const View& view = capture.views[mv.capture_view];
    if (vm.masks.empty()) continue;
    RenderSettings depth_only;
    depth_only.rgb = false;
    depth_only.depth = true;
    depth_only.normalize_depth = true;
    std::vector<cv::Mat1b> pixels;
    for (const Mask& m : vm.masks) pixels.push_back(m.pixels);
    const std::vector<float> scales =
        mask_scales(render(model, view.camera, view.pose, depth_only).depth, view.camera, pixels,
                    o.scale_swap_axes);
    std::vector<size_t> order(scales.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return scales[a] > scales[b]; });
    ViewMasks sorted{vm.view, {}};
    GatedView g;
    for (size_t i : order) {
      sorted.masks.push_back(vm.masks[i]);
      g.scales.push_back(scales[i]);
      g.areas.push_back(static_cast<float>(cv::countNonZero(vm.masks[i].pixels)));
    }
    g.masks = masked_pixels(sorted, size_t(view.camera.width) * view.camera.height);
    if (g.masks.covered.size() < 2) continue;
    all_scales.insert(all_scales.end(), g.scales.begin(), g.scales.end());
    result.masks += static_cast<int>(vm.masks.size());
    result.cache_bytes += g.masks.membership.bits.size() * sizeof(uint64_t);
    views.push_back(std::move(g));
    rows.push_back(
        render_pixel_rows(model, view.camera, view.pose, static_cast<float>(o.min_weight)));
    result.cache_bytes += rows.back().bytes();
  }
  if (views.empty())
    throw InputError("features.correspondence: no training view of capture '" + capture.name +
                     "' has pixels covered by a mask");
  result.views = static_cast<int>(views.size());
  const QuantileMap quantile(all_scales);
  const float upper = *std::max_element(all_scales.begin(), all_scales.end());

  const int dim = o.dim;
  const size_t n = model.size();
  std::vector<float> features(n * dim);
  RandomStream init(stream_seed(o.seed, "correspondence.init"));
  for (float& f : features) f = static_cast<float>(init.normal(0.0, o.init_std));
  std::vector<float> gate(2 * dim);  // Linear(1, dim): weights, then biases
  for (float& v : gate) v = static_cast<float>(init.uniform(-1.0, 1.0));
  const FeatureSmoothing smoothing(model.means, o.smooth_k);
  const int kept = std::max(1, smoothing.k() / 2);

  // The rendered attributes of iteration it: a = normalize(smooth(normalize(f))), computed once
  // per iteration (whichever batch comes first; the same values whoever computes them).
  std::vector<float> unit(n * dim), unit_norm(n), smooth(n * dim), smooth_norm(n), attr(n * dim);
  std::vector<int> slots;
  std::mutex attr_mutex;
  int attr_iteration = -1;
  auto slots_of = [&](int it) {
    std::vector<int> perm(smoothing.k());
    std::iota(perm.begin(), perm.end(), 0);
    RandomStream rng(stream_seed(o.seed, "scale_gated.smooth", static_cast<uint64_t>(it)));
    for (int i = 0; i < kept; ++i) std::swap(perm[i], perm[i + rng.below(perm.size() - i)]);
    perm.resize(kept);
    return perm;
  };
  auto attributes = [&](int it, const float* f) -> const float* {
    std::lock_guard<std::mutex> lock(attr_mutex);
    if (attr_iteration != it) {
      slots = slots_of(it);
      normalise(f, n, dim, unit.data(), unit_norm.data());
      smoothing.smooth(unit.data(), dim, slots, smooth.data());
      normalise(smooth.data(), n, dim, attr.data(), smooth_norm.data());
      attr_iteration = it;
    }
    return attr.data();
  };
  // grad wrt a -> grad wrt f, in place, through both normalisations and the smoothing.
  std::vector<float> grad_unit(n * dim);
  auto back = [&](int, const float*, const float*, float* grad, float*) {
    through_normalise(attr.data(), smooth_norm.data(), n, dim, grad);
    std::fill(grad_unit.begin(), grad_unit.end(), 0.f);
    smoothing.backward(grad, dim, slots, grad_unit.data());
    through_normalise(unit.data(), unit_norm.data(), n, dim, grad_unit.data());
    std::copy(grad_unit.begin(), grad_unit.end(), grad);
    return 0.0;
  };

  const size_t batches = static_cast<size_t>(o.views_per_iteration);
  auto step = [&](int it, size_t b, const float* raw, const float* extras, PixelBatch& batch) {
    const float* current = attributes(it, raw);
    RandomStream rng(stream_seed(o.seed, "scale_gated.step", it * batches + b));
    batch.view = static_cast<int>(rng.below(views.size()));
    const GatedView& v = views[batch.view];
    const int m = static_cast<int>(v.scales.size());
    const int words = v.masks.membership.words;
    batch.pixels.resize(o.pixels_per_iteration);
    for (uint32_t& p : batch.pixels) p = v.masks.covered[rng.below(v.masks.covered.size())];
    const int np = static_cast<int>(batch.pixels.size());
    // Scales: one above the largest, sampled ones, the smallest (code order).
    std::vector<int> index(m);
    std::iota(index.begin(), index.end(), 0);
    const int draws = std::min(o.sampled_scales, m);
    for (int i = 0; i < draws; ++i) std::swap(index[i], index[i + rng.below(size_t(m - i))]);
    std::vector<int> chosen = {-1};
    chosen.insert(chosen.end(), index.begin(), index.begin() + draws);
    chosen.push_back(m - 1);
    float second = 0;
    for (float s : v.scales)
      if (s < upper) second = std::max(second, s);
    std::vector<float> scales;
    std::vector<Eigen::MatrixXf> gt;
    std::vector<uint64_t> bits(size_t(np) * words);
    for (int k : chosen) {
      float s = k < 0 ? upper * (1.f + static_cast<float>(rng.uniform())) : v.scales[k];
      const bool above = s >= upper;
      if (above)
        s -= (s - second) * static_cast<float>(rng.uniform());
      else if (k != m - 1)
        s -= (s - v.scales[k + 1]) * static_cast<float>(rng.uniform());
      else
        s -= s * static_cast<float>(rng.uniform());
      scales.push_back(quantile(s));
      // Per pixel its ground-truth masks at this scale: above the largest, all of them; else the
      // masks smaller than mask k whole, and of masks 0..k only the smallest holding the pixel.
      for (int i = 0; i < np; ++i) {
        const uint64_t* in = v.masks.membership.pixel(batch.pixels[i]);
        uint64_t* out = bits.data() + size_t(i) * words;
        std::copy(in, in + words, out);
        if (above) continue;
        int keep = -1;
        for (int j = k; j >= 0 && keep < 0; --j)
          if (in[j / 64] >> (j % 64) & 1) keep = j;
        for (int j = 0; j <= k; ++j)
          if (j != keep) out[j / 64] &= ~(uint64_t(1) << (j % 64));
      }
      Eigen::MatrixXf g(np, np);
      for (int i = 0; i < np; ++i)
        for (int j = i; j < np; ++j) {
          bool share = false;
          for (int w = 0; w < words && !share; ++w)
            share = bits[size_t(i) * words + w] & bits[size_t(j) * words + w];
          g(i, j) = g(j, i) = share ? 1.f : 0.f;
        }
      gt.push_back(std::move(g));
    }
    std::vector<float> mean_area(np);
    for (int i = 0; i < np; ++i) {
      const uint64_t* in = v.masks.membership.pixel(batch.pixels[i]);
      double sum = 0;
      int count = 0;
      for (int j = 0; j < m; ++j)
        if (in[j / 64] >> (j % 64) & 1) sum += v.areas[j], ++count;
      mean_area[i] = count ? static_cast<float>(sum / count) : 0.f;
    }
    Eigen::MatrixXf rendered(dim, np);  // column-major: one column per pixel
    rows[batch.view].render(current, dim, batch.pixels, rendered.data());
    const ScaleGatedLoss l =
        scale_gated_loss(rendered.transpose(), gt, scales, scale_gated_pair_weights(mean_area),
                         std::vector<float>(extras, extras + 2 * dim), o.norm_weight,
                         stream_seed(o.seed, "scale_gated.pairs", it * batches + b));
    batch.loss = l.loss;
    batch.grad.resize(size_t(np) * dim);
    Eigen::Map<Eigen::MatrixXf>(batch.grad.data(), dim, np) = l.grad_features.transpose();
    batch.extra_offset = 0;
    batch.extra_grad.assign(l.grad_gate.data(), l.grad_gate.data() + 2 * dim);
  };
  PixelTrainingSettings s;
  s.iterations = o.iterations;
  s.dim = dim;
  s.lr = o.lr;
  s.extra_lr = o.lr;  // the code adds the gate to the features' Adam at the same rate
  const PixelTrainingLoss loss =
      train_pixel_features(rows, batches, s, step, features, gate, back, progress);
  result.loss_start = loss.start;
  result.loss_end = loss.end;

  // Output: full-K smoothed normalised features, gated at gate_scale.
  std::vector<int> all(smoothing.k());
  std::iota(all.begin(), all.end(), 0);
  normalise(features.data(), n, dim, unit.data(), unit_norm.data());
  smoothing.smooth(unit.data(), dim, all, smooth.data());
  normalise(smooth.data(), n, dim, attr.data(), smooth_norm.data());
  for (size_t g = 0; g < n; ++g)
    for (int c = 0; c < dim; ++c)
      attr[g * dim + c] *=
          1.f / (1.f + std::exp(-(gate[c] * static_cast<float>(o.gate_scale) + gate[dim + c])));
  result.model = model.with_features(std::move(attr), dim);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return result;
}

}  // namespace gslift
