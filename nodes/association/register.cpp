#include "nodes/association/register.hpp"

#include <memory>

#include <nlohmann/json.hpp>

#include "nodes/association/instance_mask_gaussian.hpp"
#include "nodes/lifting/feature_maps.hpp"
#include "runtime/atomic_file.hpp"

namespace gslift {
namespace {

// instances.json: per instance its label, the labels of the masks that chose it (in view order)
// and how many Gaussians it got, so a run's association can be inspected without the model.
std::string instances_json(const InstanceSet& set, const MaskSet& masks,
                           const std::vector<int32_t>& gaussian_instance) {
  std::vector<std::vector<std::string>> mask_labels(set.size());
  std::vector<int> gaussians(set.size(), 0);
  for (size_t v = 0; v < masks.views.size(); ++v)
    for (size_t m = 0; m < masks.views[v].masks.size(); ++m)
      if (set.mask_instance[v][m] >= 0)
        mask_labels[set.mask_instance[v][m]].push_back(masks.views[v].masks[m].label);
  for (const int32_t k : gaussian_instance)
    if (k >= 0) ++gaussians[k];
  nlohmann::json out = nlohmann::json::array();
  for (int k = 0; k < set.size(); ++k)
    out.push_back({{"instance", k},
                   {"label", set.labels[k]},
                   {"mask_labels", mask_labels[k]},
                   {"gaussians", gaussians[k]}});
  return out.dump(2) + "\n";
}

void run_association(NodeContext& ctx, const AssociationParams& p) {
  const auto model = ctx.input<GaussianModel>("model");
  const auto capture = ctx.input<Capture>("capture");
  const auto masks = ctx.input<MaskSet>("masks");
  const TrainingFeatureMaps views =
      render_training_feature_maps(*model, *capture, *masks, /*with_contribution=*/true);
  ctx.check_cancelled();
  InstanceAssociation a =
      associate_instances(views, *masks, *ctx.input<LiftedInstances>("instances"), *model,
                          *ctx.input<TextEncoder>("encoder"), p);
  int labelled = 0, assigned = 0;
  for (const auto& label : a.instances.labels) labelled += !label.empty();
  for (const int32_t k : a.gaussian_instance) assigned += k >= 0;
  ctx.record("instances", static_cast<double>(a.instances.size()));
  ctx.record("labelled_instances", static_cast<double>(labelled));
  ctx.record("training_masks", static_cast<double>(a.training_masks));
  ctx.record("matched_masks", static_cast<double>(a.matched_masks));
  ctx.record("assigned_gaussian_fraction",
             model->size() ? static_cast<double>(assigned) / model->size() : 0.0);
  const auto dir = ctx.out_dir();
  if (!dir.empty())
    write_file_atomically(dir / "instances.json",
                          instances_json(a.instances, *masks, a.gaussian_instance));

  GaussianModel out = *model;
  out.instance_ids = std::move(a.gaussian_instance);
  ctx.output("model", std::move(out));
  ctx.output("instances", std::move(a.instances));
}

}  // namespace

void register_association_nodes(Registry& registry) {
  NodeSpec spec{
      "association.instance_mask_gaussian",
      "LangOR 3.3 matching: training-mask pixels and masks to lifted instances, Gaussians to "
      "their most similar prototype, instance semantics from the masks' labels",
      {{"model", PortTypeName<GaussianModel>::value, "Gaussians with trained instance features"},
       {"capture", PortTypeName<Capture>::value, "the posed views (training views are used)"},
       {"masks", PortTypeName<MaskSet>::value,
        "the masks the instances were lifted from; those of held-out views are not matched"},
       {"instances", PortTypeName<LiftedInstances>::value, "lifting.cvp / lifting.mask_level"},
       {"encoder", PortTypeName<TextEncoder>::value, "encodes the masks' labels"}},
      {{"model", PortTypeName<GaussianModel>::value,
        "the input model with instance_ids (-1: background or unseen Gaussian)"},
       {"instances", PortTypeName<InstanceSet>::value,
        "prototypes, labels (\"\" = no mask, keep out of retrieval), text embeddings; "
        "mask_instance indexed like the input masks (-1 for held-out views)"}}};
  registry.add(std::move(spec), association_param_table(), run_association);
}

}  // namespace gslift
