#include "nodes/association/register.hpp"

#include <algorithm>
#include <memory>

#include <nlohmann/json.hpp>

#include "base/atomic_file.hpp"
#include "nodes/association/instance_mask_gaussian.hpp"
#include "nodes/association/memory_bank.hpp"
#include "nodes/association/sam_partition.hpp"
#include "nodes/splat/training_feature_maps.hpp"
#include "runtime/empty_result.hpp"

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

void run_association(NodeContext& ctx, const EmptyAllowed<AssociationParams>& params) {
  const AssociationParams& p = params.options;
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

  fail_if_empty(assigned == 0, params.allow_empty, "association.instance_mask_gaussian",
                a.instances.size() == 0
                    ? std::string("no instance to associate (the lifting found none)")
                    : "no Gaussian joined any of the " + std::to_string(a.instances.size()) +
                          " instances (min_similarity, min_contribution)");
  GaussianModel out = *model;
  out.instance_ids = std::move(a.gaussian_instance);
  ctx.output("model", std::move(out));
  ctx.output("instances", std::move(a.instances));
}

struct SamPartitionOptions {
  int granularity = 0;       // SAM level: 0 whole (Gaga, Proto-SaGa), 1 part
  double min_visible = 0.1;  // Gaga's "compression" ratio
};

const ParamTable<SamPartitionOptions>& sam_partition_param_table() {
  using O = SamPartitionOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("granularity", &O::granularity, "SAM mask level painted (0 whole, 1 part)", 0, 16)
          .add("min_visible", &O::min_visible,
               "a mask keeps its id when more than this share of it stays visible (Gaga: 0.1)", 0,
               1);
  return table;
}

void run_sam_partition(NodeContext& ctx, const SamPartitionOptions& o) {
  const auto capture = ctx.input<Capture>("capture");
  const auto masks = ctx.input<MaskSet>("masks");
  LabelMapSet out;
  double ids = 0;
  for (const MaskView& mv : training_mask_views(*capture, *masks)) {
    const View& view = capture->views[mv.capture_view];
    LabelMap m{view.name,
               sam_partition(masks->views[mv.mask_view], o.granularity,
                             cv::Size(view.camera.width, view.camera.height), o.min_visible)};
    int top = 0;
    for (const int id : m.labels) top = std::max(top, id);
    ids += top;
    out.labels = std::max(out.labels, top);
    out.views.push_back(std::move(m));
  }
  ctx.record("views", static_cast<double>(out.views.size()));
  ctx.record("masks_per_view", out.views.empty() ? 0.0 : ids / out.views.size());
  ctx.output("partitions", std::move(out));
}

void run_memory_bank(NodeContext& ctx, const MemoryBankOptions& o) {
  const auto model = ctx.input<GaussianModel>("model");
  const auto capture = ctx.input<Capture>("capture");
  std::shared_ptr<const ViewClassifiers> classifiers;
  if (ctx.has_input("classifiers")) classifiers = ctx.input<ViewClassifiers>("classifiers");
  AssociationResult r = associate_masks(*model, *capture, *ctx.input<LabelMapSet>("partitions"),
                                        classifiers.get(), o);
  double ms = 0;
  for (const double t : r.view_ms) ms += t;
  ctx.record("entries", static_cast<double>(r.consistent.labels));
  ctx.record("views", static_cast<double>(r.view_ms.size()));
  ctx.record("ms_per_view", ms / r.view_ms.size());
  const auto dir = ctx.out_dir();
  if (!dir.empty()) write_label_map_files(r.consistent, capture.get(), dir);
  ctx.output("labels", std::move(r.consistent));
}

void add_memory_bank_nodes(Registry& registry) {
  registry.add(NodeSpec{"association.sam_partition",
                        "SAM automatic masks of the training views painted into one id map each "
                        "(Gaga get_raw_mask.py: score order, 10% visibility, ids 1..K)",
                        {{"capture", PortTypeName<Capture>::value, "the posed views"},
                         {"masks", PortTypeName<MaskSet>::value,
                          "SAM automatic masks with granularity (ingest.sam_masks kind auto)"}},
                        {{"partitions", PortTypeName<LabelMapSet>::value,
                          "the inconsistent raw id map of each training view"}}},
               sam_partition_param_table(), run_sam_partition);
  registry.add(
      NodeSpec{"association.memory_bank",
               "consistent labels across training views: Gaga's memory bank, semantic-aware "
               "(Proto-SaGa Eq. 9-16: depth and/or view-classifier probability criteria)",
               {{"model", PortTypeName<GaussianModel>::value,
                 "Gaussians (features needed by the probability criterion)"},
                {"capture", PortTypeName<Capture>::value, "the posed views"},
                {"partitions", PortTypeName<LabelMapSet>::value,
                 "raw SAM id maps (association.sam_partition)"},
                {"classifiers", PortTypeName<ViewClassifiers>::value,
                 "per-view classifiers (features.view_classifiers); needed unless criteria: depth",
                 true}},
               {{"labels", PortTypeName<LabelMapSet>::value,
                 "one consistent label map per training view (ids = bank entries)"}}},
      memory_bank_param_table(), run_memory_bank);
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
  registry.add(std::move(spec),
               with_allow_empty(association_param_table(), "no Gaussian in any instance"),
               run_association);
  add_memory_bank_nodes(registry);
}

}  // namespace gslift
