#include "nodes/splat/density_control.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "base/random.hpp"

namespace gslift {
namespace {

// Copies row `from` of every per-Gaussian array of `src` to row `to` of `dst`.
void copy_row(const GaussianModel& src, size_t from, GaussianModel& dst, size_t to) {
  auto copy = [&](const std::vector<float>& s, std::vector<float>& d, size_t width) {
    std::copy_n(s.begin() + from * width, width, d.begin() + to * width);
  };
  copy(src.means, dst.means, 3);
  copy(src.log_scales, dst.log_scales, 3);
  copy(src.quats, dst.quats, 4);
  copy(src.opacity_logits, dst.opacity_logits, 1);
  copy(src.sh, dst.sh, GaussianModel::sh_coeffs(src.sh_degree) * 3);
  copy(src.features, dst.features, src.feature_dim);
  if (!src.instance_ids.empty()) dst.instance_ids[to] = src.instance_ids[from];
  if (!src.class_ids.empty()) dst.class_ids[to] = src.class_ids[from];
}

float max_scale(const GaussianModel& m, size_t i) {
  const float* s = &m.log_scales[i * 3];
  return std::exp(std::max({s[0], s[1], s[2]}));
}

}  // namespace

void DensityStats::add(const std::vector<float>& mean2d_abs, const std::vector<int32_t>& seen) {
  if (grad_sum.size() < mean2d_abs.size()) {
    grad_sum.resize(mean2d_abs.size(), 0.0);
    visible.resize(mean2d_abs.size(), 0);
  }
  for (size_t i = 0; i < mean2d_abs.size(); ++i) grad_sum[i] += mean2d_abs[i];
  for (size_t i = 0; i < seen.size(); ++i) visible[i] += seen[i];
}

void DensityStats::remap(const std::vector<int>& source) {
  std::vector<double> g(source.size(), 0.0);
  std::vector<int> v(source.size(), 0);
  for (size_t i = 0; i < source.size(); ++i)
    if (source[i] >= 0 && static_cast<size_t>(source[i]) < grad_sum.size()) {
      g[i] = grad_sum[source[i]];
      v[i] = visible[source[i]];
    }
  grad_sum = std::move(g);
  visible = std::move(v);
}

bool is_density_step(const DensityControlOptions& o, int step, int iterations) {
  const int stop = static_cast<int>(o.stop * iterations);
  return o.interval > 0 && step >= o.start && step <= stop && (step - o.start) % o.interval == 0;
}

namespace {

// Rows to prune, each counted in `change` under its first reason.
std::vector<char> mark_pruned(const GaussianModel& model, const DensityControlOptions& o,
                              double extent, const std::vector<char>& also_prune,
                              DensityChange& change) {
  const size_t n = model.size();
  std::vector<char> prune(n, 0);
  for (size_t i = 0; i < n; ++i) {
    const double opacity = 1 / (1 + std::exp(-static_cast<double>(model.opacity_logits[i])));
    if (opacity < o.prune_opacity)
      ++change.pruned_opacity;
    else if (max_scale(model, i) > o.prune_max_scale * extent)
      ++change.pruned_scale;
    else if (i < also_prune.size() && also_prune[i])
      ++change.pruned_marked;
    else
      continue;
    prune[i] = 1;
  }
  change.pruned = std::count(prune.begin(), prune.end(), 1);
  return prune;
}

struct Growth {
  std::vector<size_t> clones, splits;  // ascending row order
};

// Growth candidates by mean view-space gradient, largest first (index breaks ties, so the
// choice is deterministic), cloned when small and split when large (3DGS Sec. 5.2), until the
// Gaussian budget is spent.
Growth choose_growth(const GaussianModel& model, const DensityStats& stats,
                     const DensityControlOptions& o, double extent, const std::vector<char>& prune,
                     DensityChange& change) {
  const size_t n = model.size();
  std::vector<std::pair<double, size_t>> grow;
  for (size_t i = 0; i < n && i < stats.grad_sum.size(); ++i) {
    if (prune[i] || stats.visible[i] == 0) continue;
    const double mean = stats.grad_sum[i] / stats.visible[i];
    if (mean > o.grad_threshold) grow.emplace_back(-mean, i);
  }
  std::sort(grow.begin(), grow.end());
  const size_t kept_before = n - change.pruned;
  // Each clone adds one Gaussian, each split adds split_children - 1.
  size_t budget_left = o.max_gaussians > kept_before ? o.max_gaussians - kept_before : 0;
  std::vector<char> clone(n, 0), split(n, 0);
  for (size_t g = 0; g < grow.size(); ++g) {
    const size_t i = grow[g].second;
    const bool small = max_scale(model, i) <= o.clone_max_scale * extent;
    const size_t cost = small ? 1 : static_cast<size_t>(std::max(o.split_children - 1, 0));
    if (cost > budget_left) {
      change.refused = grow.size() - g;
      break;
    }
    budget_left -= cost;
    (small ? clone : split)[i] = 1;
  }
  Growth out;
  for (size_t i = 0; i < n; ++i) {
    if (clone[i]) out.clones.push_back(i);
    if (split[i]) out.splits.push_back(i);
    if (!prune[i] && !split[i]) change.source.push_back(static_cast<int>(i));
  }
  change.cloned = out.clones.size();
  change.split = out.splits.size();
  return out;
}

// The new model: kept rows (change.source so far), then clones, then split children sampled
// from N(mu, Sigma) of their parent (3DGS densify_and_split) and shrunk.
GaussianModel grown_model(const GaussianModel& model, const Growth& growth,
                          const DensityControlOptions& o, uint64_t seed, DensityChange& change) {
  const size_t total = change.source.size() + growth.clones.size() +
                       growth.splits.size() * std::max(o.split_children, 0);
  GaussianModel out;
  out.sh_degree = model.sh_degree;
  out.feature_dim = model.feature_dim;
  if (!model.instance_ids.empty()) out.instance_ids.assign(total, -1);
  if (!model.class_ids.empty()) out.class_ids.assign(total, -1);
  out.resize(total);
  size_t row = 0;
  for (int i : change.source) copy_row(model, i, out, row++);
  for (size_t i : growth.clones) {
    copy_row(model, i, out, row++);
    change.source.push_back(-1);
  }
  const float shrink = std::log(static_cast<float>(o.split_scale_divisor));
  for (size_t i : growth.splits) {
    RandomStream rng(stream_seed(seed, "densify.split", i));
    const Eigen::Matrix3d R = model.rotation(i);
    for (int c = 0; c < o.split_children; ++c) {
      Eigen::Vector3d z;
      for (int k = 0; k < 3; ++k) z[k] = rng.normal() * std::exp(model.log_scales[i * 3 + k]);
      const Eigen::Vector3d offset = R * z;
      copy_row(model, i, out, row);
      for (int k = 0; k < 3; ++k) {
        out.means[row * 3 + k] += static_cast<float>(offset[k]);
        out.log_scales[row * 3 + k] -= shrink;
      }
      ++row;
      change.source.push_back(-1);
    }
  }
  return out;
}

}  // namespace

DensityChange densify_and_prune(GaussianModel& model, const DensityStats& stats,
                                const DensityControlOptions& o, double extent, uint64_t seed,
                                const std::vector<char>& also_prune) {
  DensityChange change;
  const std::vector<char> prune = mark_pruned(model, o, extent, also_prune, change);
  const Growth growth = choose_growth(model, stats, o, extent, prune, change);
  model = grown_model(model, growth, o, seed, change);
  return change;
}

}  // namespace gslift
