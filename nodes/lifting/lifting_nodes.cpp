#include "nodes/lifting/lifting_nodes.hpp"

#include <stdexcept>
#include <string>

#include "nodes/lifting/cvp_lifting.hpp"
#include "nodes/lifting/feature_maps.hpp"

namespace gslift {
namespace {

std::vector<PortSpec> lifting_inputs() {
  return {{"model", PortTypeName<GaussianModel>::value,
           "Gaussians with trained instance features (features.contrastive)"},
          {"capture", PortTypeName<Capture>::value,
           "the posed views; feature maps are rendered at its training views"},
          {"masks", PortTypeName<MaskSet>::value,
           "2D instance masks per view; those of held-out views are ignored"}};
}

std::vector<PortSpec> lifting_outputs() {
  return {{"instances", PortTypeName<LiftedInstances>::value,
           "the lifted 3D instances: clustered samples and one prototype per instance (Eq. 5)"}};
}

// The params both lifting nodes share: HDBSCAN (with each node's defaults) and the cannot-link
// threshold.
std::vector<ParamSpec> lifting_params(const HdbscanParams& d) {
  return {int_param("min_cluster_size", d.min_cluster_size,
                    "HDBSCAN: smallest group of samples that counts as an instance", 2),
          int_param("min_samples", d.min_samples,
                    "HDBSCAN: core-distance neighbourhood, not counting the point itself (Python "
                    "hdbscan's convention); 0 = min_cluster_size",
                    0),
          float_param("epsilon", d.cluster_selection_epsilon,
                      "HDBSCAN cluster_selection_epsilon (LaGa 0.1, SAGA 0.01); 0 = off", 0),
          string_param("metric", d.metric == HdbscanMetric::Cosine ? "cosine" : "euclidean",
                       "feature distance: cosine (the contrastive loss shapes features by cosine) "
                       "or euclidean",
                       {"cosine", "euclidean"}),
          float_param("cannot_link_iou", CvpLiftingParams{}.cannot_link_iou,
                      "masks of one view overlapping less than this are different objects: no "
                      "instance may take most samples of two of them (gslift addition; 0 = off, "
                      "the paper's plain HDBSCAN)",
                      0, 1)};
}

HdbscanParams read_hdbscan(const NodeContext& ctx) {
  HdbscanParams p = default_lifting_hdbscan();
  p.min_cluster_size = static_cast<int>(ctx.param_int("min_cluster_size"));
  p.min_samples = static_cast<int>(ctx.param_int("min_samples"));
  p.cluster_selection_epsilon = ctx.param_float("epsilon");
  p.metric = parse_hdbscan_metric(ctx.param_string("metric"));
  return p;
}

// Runs `lift` on the training views' feature maps and publishes its result. The algorithms throw
// std::invalid_argument only for unusable data (e.g. an all-zero feature under the cosine
// metric), which is the input's fault.
template <class Lift>
void run_lifting(NodeContext& ctx, const Lift& lift) {
  const auto model = ctx.input<GaussianModel>("model");
  const auto capture = ctx.input<Capture>("capture");
  const auto masks = ctx.input<MaskSet>("masks");
  const TrainingFeatureMaps views =
      render_training_feature_maps(*model, *capture, *masks, /*with_contribution=*/false);
  ctx.check_cancelled();
  LiftedInstances lifted;
  try {
    lifted = lift(views);
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string(e.what()) + " (capture '" + capture->name + "')");
  }
  int noise = 0;
  for (const int label : lifted.labels) noise += label < 0;
  ctx.record("training_views", static_cast<double>(views.maps.size()));
  ctx.record("samples", static_cast<double>(lifted.samples.size()));
  ctx.record("instances", static_cast<double>(lifted.prototypes.rows()));
  ctx.record("noise_fraction",
             lifted.labels.empty() ? 0.0 : static_cast<double>(noise) / lifted.labels.size());
  ctx.output("instances", std::move(lifted));
}

void add_cvp(Registry& registry) {
  const CvpLiftingParams d;
  std::vector<ParamSpec> params = {
      float_param("sigma", d.sigma,
                  "Eq. 4 sampling width in units of each mask's RMS radius (paper 0.5; ablation "
                  "0.7)",
                  1e-3),
      int_param("samples_per_mask", d.samples_per_mask,
                "draws per mask (with replacement, then deduplicated)", 1),
      int_param("max_samples", d.max_samples, "cap on all draws (HDBSCAN is O(n^2))", 2,
                static_cast<double>(kHdbscanMaxPoints))};
  for (ParamSpec& p : lifting_params(d.hdbscan)) params.push_back(std::move(p));
  NodeSpec spec{"lifting.cvp",
                "cross-view pixel lifting (LangOR Eq. 4-5): Gaussian-weighted pixel samples of "
                "every training mask, HDBSCAN over their rendered features, one prototype per "
                "instance",
                lifting_inputs(), lifting_outputs(), std::move(params)};
  registry.add(std::move(spec), [](NodeContext& ctx) {
    CvpLiftingParams p;
    p.sigma = ctx.param_float("sigma");
    p.samples_per_mask = static_cast<int>(ctx.param_int("samples_per_mask"));
    p.max_samples = static_cast<int>(ctx.param_int("max_samples"));
    p.hdbscan = read_hdbscan(ctx);
    p.cannot_link_iou = ctx.param_float("cannot_link_iou");
    p.seed = ctx.seed();
    run_lifting(ctx, [&](const TrainingFeatureMaps& v) { return cvp_lifting(v.maps, v.masks, p); });
  });
}

// Mask-level defaults [decision]: an instance is a handful of masks (one per training view that
// sees it, 4 in LangOR's split), not hundreds of pixels, so the CVP node's min_cluster_size 10
// would leave everything noise. 2 masks make an instance; min_samples 1 makes the core distance
// the nearest other mask's.
HdbscanParams mask_level_hdbscan() {
  HdbscanParams p = default_lifting_hdbscan();
  p.min_cluster_size = 2;
  p.min_samples = 1;
  return p;
}

void add_mask_level(Registry& registry) {
  NodeSpec spec{"lifting.mask_level",
                "mask-level lifting (LangOR's w/o CVP-L ablation, LaGa-style): HDBSCAN over one "
                "masked-mean feature per training mask",
                lifting_inputs(), lifting_outputs(), lifting_params(mask_level_hdbscan())};
  registry.add(std::move(spec), [](NodeContext& ctx) {
    const HdbscanParams p = read_hdbscan(ctx);
    const double cannot_link_iou = ctx.param_float("cannot_link_iou");
    run_lifting(ctx, [&](const TrainingFeatureMaps& v) {
      return mask_level_lifting(v.maps, v.masks, p, cannot_link_iou);
    });
  });
}

}  // namespace

void add_lifting_nodes(Registry& registry) {
  add_cvp(registry);
  add_mask_level(registry);
}

}  // namespace gslift
