#include "nodes/association/instance_mask_gaussian.hpp"

#include <algorithm>
#include <string>
#include <utility>

#include <tbb/parallel_for.h>

#include "base/errors.hpp"
#include "nodes/association/instance_semantics.hpp"

namespace gslift {
namespace {

// Prototypes with unit rows: argmax_k cos(f, f_k) is then argmax_k <f, f_k / |f_k|>, since |f|
// is common to every k.
Eigen::MatrixXf unit_rows(const Eigen::MatrixXf& prototypes) {
  Eigen::MatrixXf unit = prototypes;
  for (Eigen::Index k = 0; k < unit.rows(); ++k) {
    const float norm = unit.row(k).norm();
    if (norm > 0) unit.row(k) /= norm;
  }
  return unit;
}

struct Nearest {
  int instance = -1;
  float cosine = -2.f;
};

// The most similar prototype of feature f (dim = unit.cols()); -1 for a zero feature or no
// prototypes. Ties go to the lower instance id.
Nearest nearest_prototype(const float* f, const Eigen::MatrixXf& unit) {
  const Eigen::Map<const Eigen::VectorXf> feature(f, unit.cols());
  const float norm = feature.norm();
  Nearest best;
  if (norm == 0) return best;
  for (Eigen::Index k = 0; k < unit.rows(); ++k) {
    const float c = unit.row(k).dot(feature) / norm;
    if (c > best.cosine) best = {static_cast<int>(k), c};
  }
  return best;
}

// lifted.samples grouped by (view, mask): (row-major pixel index, label) of each sampled pixel.
// CVP samples name pixels; a mask-level sample (x = y = -1) names a whole mask and no pixel, so
// all of that mask's pixels count as unsampled.
std::vector<std::vector<std::vector<std::pair<int, int>>>> sampled_pixels(
    const std::vector<FeatureMap>& maps, const MaskSet& masks, const LiftedInstances& lifted) {
  if (lifted.labels.size() != lifted.samples.size())
    throw InputError("lifted instances: " + std::to_string(lifted.samples.size()) +
                     " samples but " + std::to_string(lifted.labels.size()) + " labels");
  std::vector<std::vector<std::vector<std::pair<int, int>>>> out(masks.views.size());
  for (size_t v = 0; v < masks.views.size(); ++v) out[v].resize(masks.views[v].masks.size());
  for (size_t i = 0; i < lifted.samples.size(); ++i) {
    const SampledPixel& s = lifted.samples[i];
    const bool known_mask = s.view >= 0 && s.view < static_cast<int>(masks.views.size()) &&
                            s.mask >= 0 &&
                            s.mask < static_cast<int>(masks.views[s.view].masks.size());
    if (!known_mask)
      throw InputError("lifted instances: sample " + std::to_string(i) + " names mask " +
                       std::to_string(s.mask) + " of view " + std::to_string(s.view) +
                       ", which these masks do not have (lifted from other masks?)");
    if (s.x < 0 && s.y < 0) continue;
    const cv::Mat1b& pixels = masks.views[s.view].masks[s.mask].pixels;
    if (s.x >= pixels.cols || s.y >= pixels.rows || s.x < 0 || s.y < 0 || !pixels(s.y, s.x))
      throw InputError("lifted instances: sample " + std::to_string(i) + " at (" +
                       std::to_string(s.x) + ", " + std::to_string(s.y) + ") is not in mask " +
                       std::to_string(s.mask) + " of view '" + masks.views[s.view].view + "'");
    if (lifted.labels[i] >= lifted.prototypes.rows())
      throw InputError("lifted instances: label " + std::to_string(lifted.labels[i]) +
                       " has no prototype");
    out[s.view][s.mask].emplace_back(s.y * maps[s.view].width + s.x, lifted.labels[i]);
  }
  for (auto& view : out)
    for (auto& mask : view) std::sort(mask.begin(), mask.end());
  return out;
}

}  // namespace

const EnumNames<MaskVote>& mask_vote_names() {
  static const EnumNames<MaskVote> names = {{MaskVote::Count, "count"}, {MaskVote::Iou, "iou"}};
  return names;
}

std::vector<std::vector<int>> match_masks(const std::vector<FeatureMap>& maps, const MaskSet& masks,
                                          const LiftedInstances& lifted, MaskVote vote,
                                          float min_similarity) {
  if (maps.size() != masks.views.size())
    throw InputError(std::to_string(maps.size()) + " feature maps but " +
                     std::to_string(masks.views.size()) + " views of masks");
  for (size_t v = 0; v < maps.size(); ++v) {
    if (maps[v].dim != lifted.prototypes.cols())
      throw InputError("feature maps have " + std::to_string(maps[v].dim) +
                       " channels but the instance prototypes " +
                       std::to_string(lifted.prototypes.cols()));
    for (const Mask& m : masks.views[v].masks)
      if (m.pixels.cols != maps[v].width || m.pixels.rows != maps[v].height)
        throw InputError("a mask of view '" + masks.views[v].view +
                         "' does not match its feature map's size");
  }
  const auto sampled = sampled_pixels(maps, masks, lifted);
  const Eigen::MatrixXf unit = unit_rows(lifted.prototypes);
  const int instances = static_cast<int>(unit.rows());

  // MaskVote::Iou: each view's instance map (-1 = none) and the size of each region.
  std::vector<std::vector<int>> region(vote == MaskVote::Iou ? maps.size() : 0);
  std::vector<std::vector<int64_t>> region_size(region.size(), std::vector<int64_t>(instances, 0));
  tbb::parallel_for(size_t{0}, region.size(), [&](size_t v) {
    const FeatureMap& map = maps[v];
    region[v].resize(static_cast<size_t>(map.width) * map.height);
    for (int y = 0; y < map.height; ++y)
      for (int x = 0; x < map.width; ++x) {
        const Nearest n = nearest_prototype(map.at(x, y), unit);
        region[v][static_cast<size_t>(y) * map.width + x] =
            n.cosine >= min_similarity ? n.instance : -1;
      }
    for (const auto& mask : sampled[v])
      for (const auto& [index, label] : mask) region[v][index] = label;
    for (const int k : region[v])
      if (k >= 0) ++region_size[v][k];
  });

  std::vector<std::pair<int, int>> jobs;  // (view, mask)
  std::vector<std::vector<int>> out(masks.views.size());
  for (size_t v = 0; v < masks.views.size(); ++v) {
    out[v].assign(masks.views[v].masks.size(), -1);
    for (size_t m = 0; m < masks.views[v].masks.size(); ++m)
      jobs.emplace_back(static_cast<int>(v), static_cast<int>(m));
  }
  tbb::parallel_for(size_t{0}, jobs.size(), [&](size_t j) {
    const auto [v, m] = jobs[j];
    const cv::Mat1b& pixels = masks.views[v].masks[m].pixels;
    const auto& samples = sampled[v][m];
    std::vector<int64_t> votes(instances, 0);
    if (vote == MaskVote::Iou) {
      int64_t area = 0;
      for (int y = 0; y < pixels.rows; ++y)
        for (int x = 0; x < pixels.cols; ++x)
          if (pixels(y, x)) {
            ++area;
            const int k = region[v][static_cast<size_t>(y) * maps[v].width + x];
            if (k >= 0) ++votes[k];
          }
      int best = -1;
      double best_iou = 0;
      for (int k = 0; k < instances; ++k) {
        const double iou = static_cast<double>(votes[k]) /
                           static_cast<double>(area + region_size[v][k] - votes[k]);
        if (votes[k] > 0 && iou > best_iou) best = k, best_iou = iou;
      }
      out[v][m] = best;
      return;
    }
    for (int y = 0; y < pixels.rows; ++y)
      for (int x = 0; x < pixels.cols; ++x) {
        if (!pixels(y, x)) continue;
        const int index = y * maps[v].width + x;
        const auto hit =
            std::lower_bound(samples.begin(), samples.end(), std::make_pair(index, -1));
        const int instance = hit != samples.end() && hit->first == index
                                 ? hit->second
                                 : nearest_prototype(maps[v].at(x, y), unit).instance;
        if (instance >= 0) ++votes[instance];
      }
    int best = -1;
    for (int k = 0; k < instances; ++k)
      if (votes[k] > 0 && (best < 0 || votes[k] > votes[best])) best = k;
    out[v][m] = best;
  });
  return out;
}

std::vector<int32_t> match_gaussians(const GaussianModel& model,
                                     const std::vector<float>& contribution,
                                     const Eigen::MatrixXf& prototypes,
                                     const AssociationParams& params) {
  if (prototypes.rows() > 0 && prototypes.cols() != model.feature_dim)
    throw InputError("the model has " + std::to_string(model.feature_dim) +
                     " feature channels but the instance prototypes " +
                     std::to_string(prototypes.cols()));
  if (!contribution.empty() && contribution.size() != model.size())
    throw InputError("contribution has " + std::to_string(contribution.size()) + " entries for " +
                     std::to_string(model.size()) + " Gaussians");
  const Eigen::MatrixXf unit = unit_rows(prototypes);
  std::vector<int32_t> out(model.size(), -1);
  tbb::parallel_for(size_t{0}, model.size(), [&](size_t g) {
    if (!contribution.empty() && contribution[g] < params.min_contribution) return;
    const Nearest n = nearest_prototype(model.features.data() + g * model.feature_dim, unit);
    if (n.instance >= 0 && n.cosine >= params.min_similarity) out[g] = n.instance;
  });
  return out;
}

InstanceAssociation associate_instances(const TrainingFeatureMaps& views, const MaskSet& masks,
                                        const LiftedInstances& lifted, const GaussianModel& model,
                                        const TextEncoder& encoder,
                                        const AssociationParams& params) {
  const std::vector<int>& index = views.mask_views;  // training view i is masks.views[index[i]]
  bool from_masks = index.size() == views.masks.views.size();
  for (size_t i = 0; from_masks && i < index.size(); ++i)
    from_masks = index[i] >= 0 && index[i] < static_cast<int>(masks.views.size()) &&
                 masks.views[index[i]].masks.size() == views.masks.views[i].masks.size();
  if (!from_masks)
    throw InputError("association: the training feature maps do not come from the masks given");

  InstanceAssociation out;
  InstanceSet& set = out.instances;
  set.prototypes = lifted.prototypes;
  const std::vector<std::vector<int>> matched =
      match_masks(views.maps, views.masks, lifted, params.mask_vote, params.min_similarity);
  set.mask_instance.resize(masks.views.size());
  for (size_t v = 0; v < masks.views.size(); ++v)
    set.mask_instance[v].assign(masks.views[v].masks.size(), -1);
  for (size_t i = 0; i < index.size(); ++i) {
    set.mask_instance[index[i]] = matched[i];
    for (const int k : matched[i]) {
      out.matched_masks += k >= 0;
      ++out.training_masks;
    }
  }
  out.gaussian_instance = match_gaussians(model, views.contribution, lifted.prototypes, params);

  std::vector<std::vector<std::string>> labels(set.size());
  for (size_t v = 0; v < masks.views.size(); ++v)
    for (size_t m = 0; m < masks.views[v].masks.size(); ++m)
      if (set.mask_instance[v][m] >= 0)
        labels[set.mask_instance[v][m]].push_back(masks.views[v].masks[m].label);
  set.semantics = Eigen::MatrixXf::Zero(set.size(), encoder.dim());
  for (int k = 0; k < set.size(); ++k) {
    InstanceSemantics s = choose_instance_semantics(labels[k], encoder);
    set.labels.push_back(std::move(s.label));
    set.semantics.row(k) = s.embedding.transpose();
  }
  return out;
}

const ParamTable<AssociationParams>& association_param_table() {
  using O = AssociationParams;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("min_similarity", &O::min_similarity,
               "a Gaussian joins its most similar instance only at this cosine or above (0.5: "
               "midway between Eq. 3's hinge targets 1 and 0); -1 = always",
               -1, 1)
          .add("mask_vote", &O::mask_vote, mask_vote_names(),
               "how a mask picks its instance: count (the paper: most frequent among its pixels) "
               "or iou (the instance whose region in the view fits the mask best)")
          .add("min_contribution", &O::min_contribution,
               "Gaussians whose blend weight summed over the training pixels is below this stay "
               "unassigned (their features were never trained)",
               0);
  return table;
}

}  // namespace gslift
