#include "nodes/ingest/register.hpp"

#include "nodes/ingest/capture_annotations.hpp"
#include "nodes/ingest/capture_loader.hpp"
#include "nodes/ingest/capture_provider.hpp"

namespace gslift {
namespace {

PortSpec capture_port(const std::string& doc) {
  return {"capture", PortTypeName<Capture>::value, doc};
}

double count_boxes(const BoxSet& set) {
  size_t n = 0;
  for (const auto& v : set.views) n += v.boxes.size();
  return static_cast<double>(n);
}

void add_capture(Registry& registry) {
  const CaptureOptions d;
  NodeSpec spec{
      "ingest.capture",
      "open a capture folder (capture.yaml, COLMAP, transforms.json, Replica, 3DMatch) or an "
      "embedded: capture; views load lazily",
      {},
      {capture_port("posed views with depth prior and ground truth when present")},
      {required_string_param("path",
                             "capture folder or file, or <scheme>:<spec> such as embedded:or"),
       int_param("holdout_every", d.holdout_every,
                 "hold out every n-th view (NeRF protocol: 8) when capture.yaml names no test "
                 "views; 0 = none",
                 0),
       bool_param("skip_missing_images", d.skip_missing_images,
                  "COLMAP: leave out images the model lists but the images folder lacks, with a "
                  "warning, instead of failing"),
       int_param("downscale", d.downscale,
                 "integer image downscale on load; intrinsics are scaled to match", 1, 64),
       bool_param("undistort", d.undistort,
                  "undistort images of cameras with distortion on load, so views are ideal "
                  "pinholes; off keeps the images and Camera::distortion as captured")}};
  registry.add(std::move(spec), [](NodeContext& ctx) {
    CaptureOptions o;
    o.holdout_every = static_cast<int>(ctx.param_int("holdout_every"));
    o.skip_missing_images = ctx.param_bool("skip_missing_images");
    o.downscale = static_cast<int>(ctx.param_int("downscale"));
    o.undistort = ctx.param_bool("undistort");
    Capture capture = load_capture(resolve_capture_path(ctx.param_string("path")), o);
    ctx.record("views", static_cast<double>(capture.views.size()));
    ctx.record("test_views", static_cast<double>(capture.test_views().size()));
    ctx.record("points", static_cast<double>(capture.points.size()));
    ctx.output("capture", std::move(capture));
  });
}

void add_vlm(Registry& registry) {
  const VlmLoadOptions d;
  NodeSpec spec{"ingest.vlm",
                "read the capture's VLM grounding replies (vlm/<view>/round_<k>.txt) as boxes",
                {capture_port("the capture the replies belong to")},
                {{"boxes", PortTypeName<BoxSet>::value,
                  "every round's boxes per view, XYXY pixels, with round and reply position"}},
                {string_param("coords", d.coords,
                              "the VLM's coordinate space; auto = capture.yaml vlm.coords "
                              "(norm1000 without one)",
                              {"auto", "norm1000", "resized_abs", "pixels"}),
                 int_param("rounds", d.rounds,
                           "rounds to read per view; 0 = all found, n = exactly 0..n-1", 0)}};
  registry.add(std::move(spec), [](NodeContext& ctx) {
    VlmLoadOptions o;
    o.coords = ctx.param_string("coords");
    o.rounds = static_cast<int>(ctx.param_int("rounds"));
    int unparsed = 0;
    BoxSet boxes = load_vlm_boxes(*ctx.input<Capture>("capture"), o, &unparsed);
    ctx.record("boxes", count_boxes(boxes));
    ctx.record("rounds_unparsed", static_cast<double>(unparsed));
    ctx.output("boxes", std::move(boxes));
  });
}

void add_sam_masks(Registry& registry) {
  NodeSpec spec{
      "ingest.sam_masks",
      "read the capture's SAM masks: automatic (sam_auto/) or box-prompted (sam_box/)",
      {capture_port("the capture the masks belong to"),
       {"boxes", PortTypeName<BoxSet>::value,
        "kind box: the VLM boxes the masks were prompted with (default: ingest.vlm's, coords "
        "auto)",
        true}},
      {{"masks", PortTypeName<MaskSet>::value, "masks per view at the views' resolution"}},
      {string_param("kind", "auto",
                    "auto = SAM automatic masks with granularity; box = masks of the VLM boxes, "
                    "linked by box_index",
                    {"auto", "box"})}};
  registry.add(std::move(spec), [](NodeContext& ctx) {
    const Capture& capture = *ctx.input<Capture>("capture");
    MaskSet masks;
    if (ctx.param_string("kind") == "auto")
      masks = load_sam_auto_masks(capture);
    else if (ctx.has_input("boxes"))
      masks = load_sam_box_masks(capture, *ctx.input<BoxSet>("boxes"));
    else
      masks = load_sam_box_masks(capture, load_vlm_boxes(capture));
    size_t n = 0;
    for (const auto& v : masks.views) n += v.masks.size();
    ctx.record("masks", static_cast<double>(n));
    ctx.output("masks", std::move(masks));
  });
}

}  // namespace

void register_ingest_nodes(Registry& registry) {
  add_capture(registry);
  add_vlm(registry);
  add_sam_masks(registry);
}

}  // namespace gslift
