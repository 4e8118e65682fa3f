#include "nodes/ingest/register.hpp"

#include "nodes/ingest/capture_annotations.hpp"
#include "nodes/ingest/capture_inventory.hpp"
#include "nodes/ingest/capture_loader.hpp"
#include "nodes/ingest/capture_provider.hpp"
#include "runtime/empty_result.hpp"

namespace gslift {
namespace {

PortSpec capture_port(const std::string& doc, std::vector<CaptureNeed> needs = {}) {
  return {"capture", PortTypeName<Capture>::value, doc, false, std::move(needs)};
}

double count_boxes(const BoxSet& set) {
  size_t n = 0;
  for (const auto& v : set.views) n += v.boxes.size();
  return static_cast<double>(n);
}

// ingest.capture's params: where the capture is, then how it is read.
struct CaptureNodeParams {
  std::string path;
  CaptureOptions options;
};

const ParamTable<CaptureNodeParams>& capture_node_param_table() {
  using P = CaptureNodeParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .add("path", &P::path, "capture folder or file, or <scheme>:<spec> such as embedded:or")
          .required()
          .path()
          .nest(&P::options, capture_param_table());
  return table;
}

void run_capture(NodeContext& ctx, const CaptureNodeParams& p) {
  Capture capture = load_capture(resolve_capture_path(p.path), p.options);
  ctx.record("views", static_cast<double>(capture.views.size()));
  ctx.record("test_views", static_cast<double>(capture.test_views().size()));
  ctx.record("points", static_cast<double>(capture.points.size()));
  ctx.output("capture", std::move(capture));
}

void add_capture(Registry& registry) {
  NodeSpec spec{
      "ingest.capture",
      "open a capture folder (capture.yaml, COLMAP, transforms.json, Replica, 3DMatch, an OR rig "
      "time step) or an "
      "embedded: capture; views load lazily",
      {},
      {capture_port("posed views with depth prior and ground truth when present")}};
  registry.add(std::move(spec), capture_node_param_table(), run_capture);
  registry.add_capture_probe("ingest.capture", [](const std::map<std::string, ParamValue>& params) {
    const CaptureNodeParams p = capture_node_param_table().read(params, {});
    return capture_inventory(load_capture(resolve_capture_path(p.path), p.options));
  });
}

void run_vlm(NodeContext& ctx, const EmptyAllowed<VlmLoadOptions>& p) {
  int unparsed = 0;
  const Capture& capture = *ctx.input<Capture>("capture");
  BoxSet boxes = load_vlm_boxes(capture, p.options, &unparsed);
  ctx.record("boxes", count_boxes(boxes));
  ctx.record("rounds_unparsed", static_cast<double>(unparsed));
  fail_if_empty(count_boxes(boxes) == 0, p.allow_empty, "ingest.vlm",
                "no box in any of the " + std::to_string(capture.views.size()) +
                    " views of capture '" + capture.name + "' (" + std::to_string(unparsed) +
                    " replies did not parse)");
  ctx.output("boxes", std::move(boxes));
}

void add_vlm(Registry& registry) {
  NodeSpec spec{"ingest.vlm",
                "read the capture's VLM grounding replies (vlm/<view>/round_<k>.txt) as boxes",
                {capture_port("the capture the replies belong to", {{CaptureItem::VlmReplies}})},
                {{"boxes", PortTypeName<BoxSet>::value,
                  "every round's boxes per view, XYXY pixels, with round and reply position"}}};
  registry.add(std::move(spec), with_allow_empty(vlm_load_param_table(), "no box in any view"),
               run_vlm);
}

enum class SamMaskKind { Auto, Box };

struct SamMasksParams {
  SamMaskKind kind = SamMaskKind::Auto;
};

const ParamTable<SamMasksParams>& sam_masks_param_table() {
  static const EnumNames<SamMaskKind> kinds = {{SamMaskKind::Auto, "auto"},
                                               {SamMaskKind::Box, "box"}};
  static const ParamTable<SamMasksParams> table = ParamTable<SamMasksParams>().add(
      "kind", &SamMasksParams::kind, kinds,
      "auto = SAM automatic masks with granularity; box = masks of the VLM boxes, linked by "
      "box_index");
  return table;
}

// Every input it reads is a port: kind box reads the masks of the boxes wired to `boxes` (no
// hidden load of the VLM replies), kind auto reads none, so a wired `boxes` would be ignored.
void run_sam_masks(NodeContext& ctx, const SamMasksParams& p) {
  const Capture& capture = *ctx.input<Capture>("capture");
  MaskSet masks;
  if (p.kind == SamMaskKind::Auto) {
    if (ctx.has_input("boxes"))
      throw InputError(
          "ingest.sam_masks: kind auto reads the automatic masks and takes no boxes; unwire "
          "'boxes' or set kind: box");
    masks = load_sam_auto_masks(capture);
  } else {
    if (!ctx.has_input("boxes"))
      throw InputError(
          "ingest.sam_masks: kind box needs the input 'boxes' (the boxes the masks were "
          "prompted with: ingest.vlm's boxes, or boxes.cluster's clusters)");
    masks = load_sam_box_masks(capture, *ctx.input<BoxSet>("boxes"));
  }
  size_t n = 0;
  for (const auto& v : masks.views) n += v.masks.size();
  ctx.record("masks", static_cast<double>(n));
  ctx.output("masks", std::move(masks));
}

void add_sam_masks(Registry& registry) {
  NodeSpec spec{
      "ingest.sam_masks",
      "read the capture's SAM masks: automatic (sam_auto/) or box-prompted (sam_box/)",
      // Box masks are not a need: boxes.to_masks makes GrabCut masks of the boxes without one.
      {capture_port("the capture the masks belong to",
                    {{CaptureItem::SamAutoMasks, "kind", "auto"}}),
       {"boxes", PortTypeName<BoxSet>::value,
        "kind box (needed there, refused by kind auto): the boxes the masks were prompted "
        "with, each keeping its VLM round and reply position (ingest.vlm's boxes, or "
        "boxes.cluster's clusters); masks link to them by box_index",
        true}},
      {{"masks", PortTypeName<MaskSet>::value, "masks per view at the views' resolution"}}};
  registry.add(std::move(spec), sam_masks_param_table(), run_sam_masks);
}

}  // namespace

void register_ingest_nodes(Registry& registry) {
  add_capture(registry);
  add_vlm(registry);
  add_sam_masks(registry);
}

}  // namespace gslift
