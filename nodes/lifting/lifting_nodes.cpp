#include "nodes/lifting/lifting_nodes.hpp"

#include <stdexcept>
#include <string>

#include "nodes/lifting/cvp_lifting.hpp"
#include "nodes/splat/training_feature_maps.hpp"
#include "runtime/empty_result.hpp"

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

// Runs `lift` on the training views' feature maps and publishes its result. The algorithms throw
// std::invalid_argument only for unusable data (e.g. an all-zero feature under the cosine
// metric), which is the input's fault.
template <class Lift>
void run_lifting(NodeContext& ctx, bool allow_empty, const Lift& lift) {
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
  fail_if_empty(lifted.prototypes.rows() == 0, allow_empty, ctx.node().type,
                "no instance lifted from " + std::to_string(lifted.samples.size()) +
                    " samples of " + std::to_string(views.maps.size()) +
                    " training views (every sample was noise, or no view had a mask)");
  ctx.output("instances", std::move(lifted));
}

void run_cvp(NodeContext& ctx, EmptyAllowed<CvpLiftingParams> p) {
  p.options.seed = ctx.seed();
  run_lifting(ctx, p.allow_empty, [&](const TrainingFeatureMaps& v) {
    return cvp_lifting(v.maps, v.masks, p.options);
  });
}

void run_mask_level(NodeContext& ctx, const EmptyAllowed<MaskLevelLiftingParams>& p) {
  run_lifting(ctx, p.allow_empty, [&](const TrainingFeatureMaps& v) {
    return mask_level_lifting(v.maps, v.masks, p.options);
  });
}

void add_cvp(Registry& registry) {
  NodeSpec spec{"lifting.cvp",
                "cross-view pixel lifting (LangOR Eq. 4-5): Gaussian-weighted pixel samples of "
                "every training mask, HDBSCAN over their rendered features, one prototype per "
                "instance",
                lifting_inputs(), lifting_outputs()};
  registry.add(std::move(spec), with_allow_empty(cvp_lifting_param_table(), "no instance"),
               run_cvp);
}

void add_mask_level(Registry& registry) {
  NodeSpec spec{"lifting.mask_level",
                "mask-level lifting (LangOR's w/o CVP-L ablation, LaGa-style): HDBSCAN over one "
                "masked-mean feature per training mask",
                lifting_inputs(), lifting_outputs()};
  registry.add(std::move(spec), with_allow_empty(mask_level_lifting_param_table(), "no instance"),
               run_mask_level);
}

}  // namespace

void add_lifting_nodes(Registry& registry) {
  add_cvp(registry);
  add_mask_level(registry);
}

}  // namespace gslift
