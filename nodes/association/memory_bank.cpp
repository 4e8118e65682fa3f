#include "nodes/association/memory_bank.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "base/errors.hpp"

namespace gslift {

const EnumNames<AssociationCriteria>& association_criteria_names() {
  static const EnumNames<AssociationCriteria> names{
      {AssociationCriteria::Depth, "depth"},
      {AssociationCriteria::Probability, "probability"},
      {AssociationCriteria::Both, "both"}};
  return names;
}

ProjectedCentres project_centres(const std::vector<float>& means, const Camera& camera,
                                 const Pose& pose) {
  const size_t n = means.size() / 3;
  ProjectedCentres c;
  c.pixel.assign(n, -1);
  c.depth.assign(n, 0.f);
  const Eigen::Matrix3f R = pose.R.cast<float>();
  const Eigen::Vector3f t = pose.t.cast<float>();
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    const Eigen::Vector3f x = R * Eigen::Map<const Eigen::Vector3f>(&means[3 * i]) + t;
    c.depth[i] = x.z();
    if (!(x.z() > 0)) return;
    // The pixel whose centre (u + 0.5, v + 0.5) is nearest: Gaga rounds ((v + 1) S - 1) / 2, the
    // same pixel in its convention (centres at integers).
    const double u = std::floor(camera.fx * x.x() / x.z() + camera.cx);
    const double v = std::floor(camera.fy * x.y() / x.z() + camera.cy);
    if (u < 0 || v < 0 || u >= camera.width || v >= camera.height) return;
    c.pixel[i] = static_cast<int32_t>(v) * camera.width + static_cast<int32_t>(u);
  });
  return c;
}

namespace {

size_t keep_count(size_t n, double fraction) {
  return std::max<size_t>(static_cast<size_t>(std::floor(fraction * n)), 1);
}

struct Candidate {
  int32_t mask;  // raw id t
  int32_t cell;  // patch index
  float key;     // depth (ascending) or -probability (ascending = most probable first)
  uint32_t id;
  bool operator<(const Candidate& o) const {
    if (mask != o.mask) return mask < o.mask;
    if (cell != o.cell) return cell < o.cell;
    if (key != o.key) return key < o.key;
    return id < o.id;
  }
};

// Appends to sets[t - 1] the front max(floor(fraction n), 1) of every run of candidates with
// the same (mask, cell); `candidates` sorted.
void keep_front(const std::vector<Candidate>& candidates, double fraction,
                std::vector<std::vector<uint32_t>>& sets) {
  for (size_t begin = 0; begin < candidates.size();) {
    size_t end = begin + 1;
    while (end < candidates.size() && candidates[end].mask == candidates[begin].mask &&
           candidates[end].cell == candidates[begin].cell)
      ++end;
    const size_t keep = keep_count(end - begin, fraction);
    auto& set = sets[candidates[begin].mask - 1];
    for (size_t k = begin; k < begin + keep; ++k) set.push_back(candidates[k].id);
    begin = end;
  }
}

}  // namespace

std::vector<std::vector<uint32_t>> select_mask_gaussians(const cv::Mat1i& partition,
                                                         const ProjectedCentres& centres,
                                                         const std::vector<float>& probability,
                                                         const MemoryBankOptions& o) {
  if (!partition.isContinuous())
    throw InputError("association.memory_bank: the partition map must be continuous");
  const int width = partition.cols, height = partition.rows;
  int masks = 0;
  for (const int id : partition) masks = std::max(masks, id);
  const bool depth = o.criteria != AssociationCriteria::Probability;
  const bool prob = o.criteria != AssociationCriteria::Depth;
  if (prob && probability.size() != centres.pixel.size())
    throw InputError(
        "association.memory_bank: the probability criterion needs one probability per Gaussian "
        "(a view classifier)");

  std::vector<Candidate> by_patch, by_probability;
  const int* ids = partition.ptr<int>();
  for (size_t i = 0; i < centres.pixel.size(); ++i) {
    const int32_t p = centres.pixel[i];
    if (p < 0) continue;
    const int t = ids[p];
    if (t <= 0) continue;
    const int x = p % width, y = p / width;
    const int cell = (y * o.patches / height) * o.patches + x * o.patches / width;
    if (depth) by_patch.push_back({t, cell, centres.depth[i], static_cast<uint32_t>(i)});
    if (prob) by_probability.push_back({t, 0, -probability[i], static_cast<uint32_t>(i)});
  }
  std::vector<std::vector<uint32_t>> sets(masks);
  std::sort(by_patch.begin(), by_patch.end());
  keep_front(by_patch, o.front_fraction, sets);
  std::sort(by_probability.begin(), by_probability.end());
  keep_front(by_probability, o.probability_fraction, sets);
  // Union (Eq. 16): a Gaussian picked by both criteria appears twice.
  for (auto& set : sets) {
    std::sort(set.begin(), set.end());
    set.erase(std::unique(set.begin(), set.end()), set.end());
  }
  return sets;
}

std::vector<float> gaussian_mask_probabilities(const cv::Mat1i& partition,
                                               const ProjectedCentres& centres,
                                               const std::vector<float>& features, int dim,
                                               const std::vector<float>& weights, int classes,
                                               double tau) {
  const size_t n = centres.pixel.size();
  if (features.size() != n * dim || weights.size() != size_t(classes) * dim)
    throw InputError("association.memory_bank: features or view classifier do not match the model");
  // Rows of the classifier normalised once (Eq. 14 divides by |w_c|).
  std::vector<float> w(weights);
  for (int c = 0; c < classes; ++c) {
    double s = 0;
    for (int d = 0; d < dim; ++d) s += double(w[c * dim + d]) * w[c * dim + d];
    const float inv = static_cast<float>(1.0 / std::max(std::sqrt(s), 1e-12));
    for (int d = 0; d < dim; ++d) w[c * dim + d] *= inv;
  }
  std::vector<float> out(n, 0.f);
  const int* ids = partition.ptr<int>();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n), [&](const tbb::blocked_range<size_t>& r) {
    std::vector<double> logits(classes);  // one buffer per chunk, not per Gaussian
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const int32_t p = centres.pixel[i];
      if (p < 0 || ids[p] <= 0 || ids[p] >= classes) continue;
      const float* f = &features[i * dim];
      double norm = 0;
      for (int d = 0; d < dim; ++d) norm += double(f[d]) * f[d];
      const double scale = tau / std::max(std::sqrt(norm), 1e-12);
      double top = -1e300;
      for (int c = 0; c < classes; ++c) {
        double s = 0;
        for (int d = 0; d < dim; ++d) s += double(w[c * dim + d]) * f[d];
        logits[c] = scale * s;
        top = std::max(top, logits[c]);
      }
      double sum = 0;
      for (const double l : logits) sum += std::exp(l - top);
      out[i] = static_cast<float>(std::exp(logits[ids[p]] - top) / sum);
    }
  });
  return out;
}

MemoryBank::MemoryBank(size_t gaussians, double threshold, bool gaga_compat)
    : threshold_(threshold), gaga_compat_(gaga_compat), member_of_(gaussians) {}

void MemoryBank::insert(int entry, uint32_t gaussian) {
  auto& of = member_of_[gaussian];
  if (std::find(of.begin(), of.end(), entry) != of.end()) return;
  of.push_back(entry);
  entries_[entry].push_back(gaussian);
}

std::vector<double> MemoryBank::overlaps(const std::vector<uint32_t>& set) const {
  std::vector<double> gamma(entries_.size(), 0.0);
  if (set.empty()) return gamma;
  for (const uint32_t g : set)
    for (const int32_t e : member_of_[g]) gamma[e] += 1;
  for (double& inter : gamma)
    inter = gaga_compat_ ? inter / (set.size() + inter + 1e-8) : inter / set.size();
  return gamma;
}

std::vector<int> MemoryBank::add_view(const std::vector<std::vector<uint32_t>>& sets) {
  const bool first = entries_.empty();
  std::vector<int> labels(sets.size());
  for (size_t t = 0; t < sets.size(); ++t) {
    const auto& set = sets[t];
    int best = -1;
    if (!first) {
      const std::vector<double> gamma = overlaps(set);
      double top = 0;
      for (size_t e = 0; e < gamma.size(); ++e)
        if (gamma[e] > top) top = gamma[e], best = static_cast<int>(e);
      if (best >= 0 && !(top >= threshold_)) best = -1;
    }
    if (best < 0) {
      // A new entry takes the whole set (both modes).
      best = static_cast<int>(entries_.size());
      entries_.emplace_back();
      for (const uint32_t g : set) insert(best, g);
    } else {
      for (const uint32_t g : set)
        if (!gaga_compat_ || member_of_[g].empty()) insert(best, g);
    }
    labels[t] = best + 1;
  }
  return labels;
}

cv::Mat1i relabel_partition(const cv::Mat1i& partition, const std::vector<int>& labels) {
  cv::Mat1i out(partition.size());
  std::transform(partition.begin(), partition.end(), out.begin(),
                 [&](int t) { return t > 0 && size_t(t) <= labels.size() ? labels[t - 1] : 0; });
  return out;
}

AssociationResult associate_masks(const GaussianModel& model, const Capture& capture,
                                  const LabelMapSet& partitions, const ViewClassifiers* classifiers,
                                  const MemoryBankOptions& o) {
  memory_bank_param_table().validate(o, "association.memory_bank");
  const bool prob = o.criteria != AssociationCriteria::Depth;
  if (prob && (!classifiers || model.feature_dim != classifiers->dim))
    throw InputError(
        "association.memory_bank: criteria '" +
        enum_name(o.criteria, association_criteria_names()) +
        "' needs the view classifiers and the model's features (features.view_classifiers)");
  AssociationResult r;
  MemoryBank bank(model.size(), o.threshold, o.gaga_compat);
  for (const LabelMap& m : partitions.views) {
    const int v = capture.find_view(m.view);
    if (v < 0)
      throw InputError("association.memory_bank: partition of view '" + m.view +
                       "' is not in capture '" + capture.name + "'");
    const View& view = capture.views[v];
    if (view.held_out) continue;
    if (m.labels.cols != view.camera.width || m.labels.rows != view.camera.height)
      throw InputError("association.memory_bank: partition of view '" + m.view +
                       "' differs in size from the view");
    const auto t0 = std::chrono::steady_clock::now();
    const cv::Mat1i partition = m.labels.isContinuous() ? m.labels : m.labels.clone();
    const ProjectedCentres centres = project_centres(model.means, view.camera, view.pose);
    std::vector<float> probability;
    if (prob) {
      const ViewClassifier* c = nullptr;
      for (const auto& k : classifiers->views)
        if (k.view == m.view) c = &k;
      if (!c)
        throw InputError("association.memory_bank: no view classifier for training view '" +
                         m.view + "'");
      probability =
          gaussian_mask_probabilities(partition, centres, model.features, model.feature_dim,
                                      c->weights, c->classes, classifiers->tau);
    }
    const std::vector<int> labels =
        bank.add_view(select_mask_gaussians(partition, centres, probability, o));
    r.consistent.views.push_back({m.view, relabel_partition(partition, labels)});
    r.view_ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  if (r.consistent.views.empty())
    throw InputError("association.memory_bank: no training view of capture '" + capture.name +
                     "' has a partition");
  r.consistent.labels = static_cast<int>(bank.entries());
  for (size_t e = 0; e < bank.entries(); ++e) r.entry_sizes.push_back(bank.entry(e).size());
  return r;
}

const ParamTable<MemoryBankOptions>& memory_bank_param_table() {
  using O = MemoryBankOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("criteria", &O::criteria, association_criteria_names(),
               "Gaussians of a mask: depth (Gaga, Eq. 10), probability (Eq. 15) or both (Eq. 16)")
          .add("front_fraction", &O::front_fraction,
               "delta_d: share of each patch's candidates kept, front first (Gaga: 0.2)", 1e-6, 1)
          .add("probability_fraction", &O::probability_fraction,
               "delta_s: share of a mask's candidates kept, most probable first (0.2)", 1e-6, 1)
          .add("patches", &O::patches, "patch grid cells per side (Gaga: 32)", 1, 4096)
          .add("threshold", &O::threshold, "delta: least overlap score to join an entry (0.1)", 0,
               1)
          .add("gaga_compat", &O::gaga_compat,
               "Gaga's code: gamma = |GnM|/(|G|+|GnM|), joins gain only unassigned Gaussians");
  return table;
}

}  // namespace gslift
