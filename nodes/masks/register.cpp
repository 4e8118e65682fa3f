#include "nodes/masks/register.hpp"

#include <map>

#include <nlohmann/json.hpp>

#include "base/atomic_file.hpp"
#include "nodes/ingest/sam_masks.hpp"
#include "nodes/masks/auto_masks.hpp"
#include "nodes/masks/geometry_masks.hpp"

namespace gslift {
namespace {

// sam_auto/<view>.json in the out folder, in the form ingest.sam_masks (kind auto) reads, so the
// masks can be inspected with SAM tooling or ingested again.
void write_sam_auto_files(const MaskSet& set, const std::filesystem::path& dir) {
  for (const ViewMasks& vm : set.views) {
    nlohmann::json list = nlohmann::json::array();
    for (const Mask& m : vm.masks) {
      nlohmann::json rec = sam_mask_record(m.pixels, m.score, 1.0);
      rec["granularity"] = m.granularity;
      list.push_back(std::move(rec));
    }
    write_file_atomically(dir / "sam_auto" / (vm.view + ".json"), list.dump());
  }
}

// The automatic-mask nodes' output: counts (per granularity too), the SAM-form files, the port.
void output_automatic_masks(NodeContext& ctx, MaskSet set) {
  size_t n = 0;
  std::map<int, size_t> per_granularity;
  for (const ViewMasks& vm : set.views) {
    n += vm.masks.size();
    for (const Mask& m : vm.masks) ++per_granularity[m.granularity];
  }
  ctx.record("views", static_cast<double>(set.views.size()));
  ctx.record("masks", static_cast<double>(n));
  for (const auto& [g, count] : per_granularity)
    ctx.record("masks/g" + std::to_string(g), static_cast<double>(count));
  const auto dir = ctx.out_dir();
  if (!dir.empty()) write_sam_auto_files(set, dir);
  ctx.output("masks", std::move(set));
}

void run_auto(NodeContext& ctx, const AutoMaskOptions& o) {
  output_automatic_masks(ctx, auto_mask_set(*ctx.input<Capture>("capture"), o));
}

void run_geometry(NodeContext& ctx, const GeometryMaskOptions& o) {
  output_automatic_masks(ctx, geometry_mask_set(*ctx.input<Capture>("capture"), o));
}

struct GroundTruthOptions {
  ViewSet views = ViewSet::All;
};

const ParamTable<GroundTruthOptions>& ground_truth_table() {
  static const ParamTable<GroundTruthOptions> table = ParamTable<GroundTruthOptions>().add(
      "views", &GroundTruthOptions::views, view_set_names(), "views whose ground truth to read");
  return table;
}

void run_ground_truth(NodeContext& ctx, const GroundTruthOptions& o) {
  const auto capture = ctx.input<Capture>("capture");
  MaskSet set = ground_truth_masks(*capture, o.views);
  if (set.views.empty())
    throw InputError("masks.ground_truth: capture '" + capture->name +
                     "' has no ground-truth instance map in the chosen views");
  ctx.record("views", static_cast<double>(set.views.size()));
  ctx.output("masks", std::move(set));
}

struct MaskFolderOptions {
  std::string folder;
  std::string label = "object";
  ViewSet views = ViewSet::All;
  MaskChannel channel = MaskChannel::Gray;
};

const ParamTable<MaskFolderOptions>& mask_folder_table() {
  using O = MaskFolderOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("folder", &O::folder,
               "folder of mask images, one per view (stem = view name or "
               "the same number); relative: to the capture's folder first")
          .required()
          .add("label", &O::label, "label of every mask (prompts and evaluation match on it)")
          .add("views", &O::views, view_set_names(), "views to read masks for")
          .add("channel", &O::channel, mask_channel_names(),
               "where the mask is: gray (a mask image) or alpha (an RGBA render's coverage)");
  return table;
}

void run_mask_folder(NodeContext& ctx, const MaskFolderOptions& o) {
  const auto capture = ctx.input<Capture>("capture");
  const std::filesystem::path folder = resolve_in_capture(capture->root, o.folder);
  MaskSet set = mask_folder(*capture, folder, o.views, o.label, o.channel);
  if (set.views.empty())
    throw InputError("masks.folder: no file of " + folder.string() + " matches a view of '" +
                     capture->name + "'");
  ctx.record("views", static_cast<double>(set.views.size()));
  ctx.output("masks", std::move(set));
}

}  // namespace

void register_masks_nodes(Registry& registry) {
  registry.add(NodeSpec{"masks.auto",
                        "class-agnostic automatic masks at several granularities from graph-based "
                        "segmentation (a fallback for SAM automatic masks)",
                        {{"capture",
                          PortTypeName<Capture>::value,
                          "views with RGB",
                          false,
                          {{CaptureItem::Images}}}},
                        {{"masks", PortTypeName<MaskSet>::value,
                          "per view the segments of every scale, with granularity (files: "
                          "sam_auto/<view>.json as SAM writes them)"}}},
               auto_mask_param_table(), run_auto);
  registry.add(NodeSpec{"masks.geometry",
                        "class-agnostic automatic masks from the depth prior: dominant planes, "
                        "depth and normal discontinuities; groups, objects and parts",
                        {{"capture",
                          PortTypeName<Capture>::value,
                          "views with a depth prior (RGB-D sensor, MVS)",
                          false,
                          {{CaptureItem::Depth}}}},
                        {{"masks", PortTypeName<MaskSet>::value,
                          "per view the segments of granularity 0 (planes, groups apart in "
                          "depth), 1 (objects: cut at concave creases) and 2 (parts: cut at every "
                          "crease) (files: sam_auto/<view>.json as SAM writes them)"}}},
               geometry_mask_param_table(), run_geometry);
  registry.add(
      NodeSpec{"masks.ground_truth",
               "the capture's ground-truth instance masks (labels = instance ids), for prompts "
               "and evaluation",
               {{"capture",
                 PortTypeName<Capture>::value,
                 "views with ground-truth instance maps",
                 false,
                 {{CaptureItem::GtInstances}}}},
               {{"masks", PortTypeName<MaskSet>::value, "per view one mask per instance"}}},
      ground_truth_table(), run_ground_truth);
  registry.add(
      NodeSpec{"masks.folder",
               "binary object masks from image files, one per view (e.g. DTU's mask/)",
               {{"capture",
                 PortTypeName<Capture>::value,
                 "the views the masks belong to",
                 false,
                 {{CaptureItem::NamedFolder, "", "", "folder",
                   "object masks, one image per view named as the view (DTU's mask/; a "
                   "NeRF-synthetic split's RGBA images with channel: alpha), drawn by hand or "
                   "by a segmentation tool"}}}},
               {{"masks", PortTypeName<MaskSet>::value, "per view one mask, labelled `label`"}}},
      mask_folder_table(), run_mask_folder);
}

}  // namespace gslift
