#include "nodes/lifting/cvp_lifting.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "nodes/lifting/alias_sampler.hpp"
#include "nodes/lifting/cvp_weights.hpp"

namespace gslift {
namespace {

void check_inputs(const std::vector<FeatureMap>& views, const MaskSet& masks) {
  if (views.size() != masks.views.size())
    throw std::invalid_argument("lifting: " + std::to_string(views.size()) + " feature maps but " +
                                std::to_string(masks.views.size()) + " views of masks");
  for (size_t v = 0; v < views.size(); ++v) {
    const FeatureMap& f = views[v];
    if (f.values.size() != static_cast<size_t>(f.width) * f.height * f.dim)
      throw std::invalid_argument("lifting: feature map of view " + std::to_string(v) +
                                  " has the wrong number of values");
    for (const Mask& m : masks.views[v].masks)
      if (m.pixels.cols != f.width || m.pixels.rows != f.height)
        throw std::invalid_argument("lifting: a mask of view '" + masks.views[v].view +
                                    "' does not match its feature map's size");
  }
}

// Eq. 5: per label, the mean of the member rows.
Eigen::MatrixXf prototypes_of(const PointMatrix& features, const std::vector<int>& labels,
                              int clusters) {
  Eigen::MatrixXd sum = Eigen::MatrixXd::Zero(clusters, features.cols());
  std::vector<double> count(clusters, 0.0);
  for (size_t i = 0; i < labels.size(); ++i) {
    if (labels[i] < 0) continue;
    sum.row(labels[i]) += features.row(i);
    count[labels[i]] += 1;
  }
  for (int c = 0; c < clusters; ++c) sum.row(c) /= count[c];
  return sum.cast<float>();
}

// The constraints of same_view_cannot_links over points that each come from one mask.
CannotLink cannot_link_for(const std::vector<SampledPixel>& samples, const MaskSet& masks,
                           double max_iou) {
  CannotLink cl;
  cl.pairs = same_view_cannot_links(masks, max_iou);
  if (cl.pairs.empty()) return cl;
  const std::vector<std::vector<int>> group = mask_group_ids(masks);
  for (const SampledPixel& s : samples) cl.point_groups.push_back(group[s.view][s.mask]);
  return cl;
}

// HDBSCAN over the samples whose feature is not zero. A pixel that no Gaussian covers renders a
// zero feature: it has no direction (no cosine distance) and would gather at the origin under the
// Euclidean metric, so it is noise (-1) and stays out of the clustering. The stability matrix met
// such pixels with 50% depth holes and 1 degree of pose noise (bench/results/stability.json), where
// HDBSCAN used to reject the whole capture.
HdbscanResult cluster_covered(const PointMatrix& features, const std::vector<SampledPixel>& samples,
                              const MaskSet& masks, const HdbscanParams& hdbscan_params,
                              double cannot_link_iou) {
  std::vector<int64_t> kept;
  for (int64_t i = 0; i < features.rows(); ++i)
    if (features.row(i).squaredNorm() > 0) kept.push_back(i);
  if (kept.size() == size_t(features.rows()))
    return hdbscan(features, hdbscan_params, cannot_link_for(samples, masks, cannot_link_iou));
  PointMatrix covered(static_cast<int64_t>(kept.size()), features.cols());
  std::vector<SampledPixel> covered_samples;
  for (size_t j = 0; j < kept.size(); ++j) {
    covered.row(static_cast<int64_t>(j)) = features.row(kept[j]);
    covered_samples.push_back(samples[size_t(kept[j])]);
  }
  const HdbscanResult part =
      hdbscan(covered, hdbscan_params, cannot_link_for(covered_samples, masks, cannot_link_iou));
  HdbscanResult all;
  all.clusters = part.clusters;
  all.labels.assign(size_t(features.rows()), -1);
  all.probabilities.assign(size_t(features.rows()), 0.0);
  for (size_t j = 0; j < kept.size(); ++j) {
    all.labels[size_t(kept[j])] = part.labels[j];
    all.probabilities[size_t(kept[j])] = part.probabilities[j];
  }
  return all;
}

}  // namespace

std::vector<std::vector<int>> mask_group_ids(const MaskSet& masks) {
  std::vector<std::vector<int>> ids(masks.views.size());
  int next = 0;
  for (size_t v = 0; v < masks.views.size(); ++v)
    for (size_t m = 0; m < masks.views[v].masks.size(); ++m) ids[v].push_back(next++);
  return ids;
}

std::vector<std::pair<int, int>> same_view_cannot_links(const MaskSet& masks, double max_iou) {
  std::vector<std::pair<int, int>> pairs;
  if (max_iou <= 0) return pairs;
  const std::vector<std::vector<int>> group = mask_group_ids(masks);
  for (size_t v = 0; v < masks.views.size(); ++v) {
    const std::vector<Mask>& ms = masks.views[v].masks;
    for (size_t a = 0; a < ms.size(); ++a)
      for (size_t b = a + 1; b < ms.size(); ++b)
        if (mask_iou(ms[a].pixels, ms[b].pixels) < max_iou)
          pairs.emplace_back(group[v][a], group[v][b]);
  }
  return pairs;
}

HdbscanParams default_lifting_hdbscan() {
  HdbscanParams p;
  p.min_cluster_size = 10;
  p.min_samples = 3;
  p.metric = HdbscanMetric::Cosine;
  return p;
}

HdbscanParams mask_level_hdbscan() {
  HdbscanParams p = default_lifting_hdbscan();
  p.min_cluster_size = 2;
  p.min_samples = 1;
  return p;
}

LiftedInstances cvp_lifting(const std::vector<FeatureMap>& views, const MaskSet& masks,
                            const CvpLiftingParams& params) {
  check_inputs(views, masks);
  // All pixels of all masks with their Eq. 4 weights, in (view, mask, row-major pixel) order.
  std::vector<SampledPixel> candidates;
  std::vector<double> weights;
  int mask_count = 0;
  for (size_t v = 0; v < views.size(); ++v)
    for (size_t m = 0; m < masks.views[v].masks.size(); ++m) {
      const MaskPixelWeights w = cvp_weights(masks.views[v].masks[m].pixels, params.sigma);
      mask_count += !w.pixels.empty();
      for (size_t i = 0; i < w.pixels.size(); ++i) {
        candidates.push_back(
            {static_cast<int>(v), static_cast<int>(m), w.pixels[i].x, w.pixels[i].y});
        weights.push_back(w.weights[i]);
      }
    }
  if (candidates.empty()) throw std::invalid_argument("lifting: the masks have no pixels");

  const int64_t budget = std::min<int64_t>(
      params.max_samples, static_cast<int64_t>(params.samples_per_mask) * mask_count);
  std::vector<int64_t> drawn = AliasSampler(weights).sample(budget, params.seed);
  std::sort(drawn.begin(), drawn.end());
  drawn.erase(std::unique(drawn.begin(), drawn.end()), drawn.end());

  LiftedInstances out;
  const int dim = views.front().dim;
  PointMatrix features(static_cast<int64_t>(drawn.size()), dim);
  for (size_t i = 0; i < drawn.size(); ++i) {
    const SampledPixel& s = candidates[drawn[i]];
    out.samples.push_back(s);
    const float* f = views[s.view].at(s.x, s.y);
    for (int k = 0; k < dim; ++k) features(static_cast<int64_t>(i), k) = f[k];
  }
  const HdbscanResult clusters =
      cluster_covered(features, out.samples, masks, params.hdbscan, params.cannot_link_iou);
  out.labels = clusters.labels;
  out.prototypes = prototypes_of(features, out.labels, clusters.clusters);
  return out;
}

LiftedInstances mask_level_lifting(const std::vector<FeatureMap>& views, const MaskSet& masks,
                                   const MaskLevelLiftingParams& params) {
  check_inputs(views, masks);
  LiftedInstances out;
  std::vector<std::vector<double>> rows;
  for (size_t v = 0; v < views.size(); ++v)
    for (size_t m = 0; m < masks.views[v].masks.size(); ++m) {
      const cv::Mat1b& pixels = masks.views[v].masks[m].pixels;
      std::vector<double> mean(views[v].dim, 0.0);
      double count = 0;
      for (int y = 0; y < pixels.rows; ++y)
        for (int x = 0; x < pixels.cols; ++x)
          if (pixels(y, x)) {
            const float* f = views[v].at(x, y);
            for (int k = 0; k < views[v].dim; ++k) mean[k] += f[k];
            count += 1;
          }
      if (count == 0) continue;
      for (double& value : mean) value /= count;
      rows.push_back(std::move(mean));
      out.samples.push_back({static_cast<int>(v), static_cast<int>(m), -1, -1});
    }
  if (rows.empty()) throw std::invalid_argument("lifting: the masks have no pixels");
  PointMatrix features(static_cast<int64_t>(rows.size()), views.front().dim);
  for (size_t i = 0; i < rows.size(); ++i)
    for (size_t k = 0; k < rows[i].size(); ++k) features(static_cast<int64_t>(i), k) = rows[i][k];
  const HdbscanResult clusters =
      cluster_covered(features, out.samples, masks, params.hdbscan, params.cannot_link_iou);
  out.labels = clusters.labels;
  out.prototypes = prototypes_of(features, out.labels, clusters.clusters);
  return out;
}

namespace {

// The HDBSCAN fields both lifting nodes expose, and the cannot-link threshold, for any params
// struct with `hdbscan` and `cannot_link_iou` members.
template <class O>
ParamTable<O> with_clustering_params(ParamTable<O> table) {
  using H = HdbscanParams;
  static const ParamTable<H> hdbscan_table =
      ParamTable<H>()
          .add("min_cluster_size", &H::min_cluster_size,
               "HDBSCAN: smallest group of samples that counts as an instance", 2)
          .add("min_samples", &H::min_samples,
               "HDBSCAN: core-distance neighbourhood, not counting the point itself (Python "
               "hdbscan's convention); 0 = min_cluster_size",
               0)
          .add("epsilon", &H::cluster_selection_epsilon,
               "HDBSCAN cluster_selection_epsilon (LaGa 0.1, SAGA 0.01); 0 = off", 0)
          .add("metric", &H::metric, hdbscan_metric_names(),
               "feature distance: cosine (the contrastive loss shapes features by cosine) or "
               "euclidean");
  return table.nest(&O::hdbscan, hdbscan_table)
      .add("cannot_link_iou", &O::cannot_link_iou,
           "masks of one view overlapping less than this are different objects: no instance may "
           "take most samples of two of them (gslift addition; 0 = off, the paper's plain "
           "HDBSCAN)",
           0, 1);
}

}  // namespace

const ParamTable<CvpLiftingParams>& cvp_lifting_param_table() {
  using O = CvpLiftingParams;
  static const ParamTable<O> table = with_clustering_params(
      ParamTable<O>()
          .add("sigma", &O::sigma,
               "Eq. 4 sampling width in units of each mask's RMS radius (paper 0.5; ablation 0.7)",
               1e-3)
          .add("samples_per_mask", &O::samples_per_mask,
               "draws per mask (with replacement, then deduplicated)", 1)
          .add("max_samples", &O::max_samples, "cap on all draws (HDBSCAN is O(n^2))", 2,
               static_cast<double>(kHdbscanMaxPoints)));
  return table;
}

const ParamTable<MaskLevelLiftingParams>& mask_level_lifting_param_table() {
  static const ParamTable<MaskLevelLiftingParams> table =
      with_clustering_params(ParamTable<MaskLevelLiftingParams>());
  return table;
}

}  // namespace gslift
