#include "nodes/ingest/capture_inventory.hpp"

#include "base/input_file.hpp"
#include "nodes/ingest/capture_manifest.hpp"
#include "nodes/ingest/or_rig.hpp"

namespace gslift {

namespace {

namespace fs = std::filesystem;

// Whether some view has `file(view)`: annotations may cover only some views, and a view without
// them is a view the model found nothing in; none at all is a capture without them.
template <class File>
bool any_view_has(const Capture& capture, File file) {
  for (const View& v : capture.views)
    if (entry_exists(file(v))) return true;
  return false;
}

template <class Has>
bool every_view(const Capture& capture, Has has) {
  for (const View& v : capture.views)
    if (!has(v)) return false;
  return !capture.views.empty();
}

template <class Has>
bool some_view(const Capture& capture, Has has) {
  for (const View& v : capture.views)
    if (has(v)) return true;
  return false;
}

std::string folder_text(const fs::path& folder) {
  return (folder / "").string();
}

}  // namespace

CaptureInventory capture_inventory(const Capture& capture) {
  CaptureInventory inv;
  const fs::path root = capture.root;
  inv.root = root;
  // A capture built in memory (no folder) holds what it was built with; it has no files beside
  // it to look for.
  const CaptureManifest m =
      root.empty() ? CaptureManifest() : read_capture_manifest(root, capture.allow_outside_paths);
  const std::string n_views = std::to_string(capture.views.size());
  const fs::path rig_step = m.rig.empty() ? root : root / m.rig;

  std::string missing_image;
  for (const View& v : capture.views)
    if (!v.rgb.present() || (!v.rgb.path().empty() && !entry_exists(v.rgb.path()))) {
      missing_image = v.rgb.path().empty() ? "view " + v.name : v.rgb.path().string();
      break;
    }
  inv[CaptureItem::Images] = {
      missing_image.empty() && !capture.views.empty(),
      missing_image.empty() ? "the views' images" : missing_image,
      "the capture's own images, named by its camera model (COLMAP images/, transforms.json "
      "file_path, an OR rig's colorimage/; docs/capture_format.md, docs/or-rig.md)"};

  inv[CaptureItem::Depth] = {
      every_view(capture, [](const View& v) { return v.depth.present(); }),
      !m.depth.empty() ? "a depth map per view in " + folder_text(root / m.depth)
      : !root.empty() && is_or_rig_step(rig_step)
          ? "a depth frame per camera in " + folder_text(rig_step / "depthimage") +
                " (<camera>_depthimage-<index>.tiff)"
          : "a depth folder (capture.yaml depth:, Replica "
            "results/depth*.png, 3DMatch *.depth.png, an OR rig's "
            "depthimage/); this capture names none",
      "a depth sensor or multi-view stereo, one 16-bit PNG (depth_scale per metre) or float "
      "TIFF per view, named in capture.yaml's depth: (docs/capture_format.md); an OR rig's "
      "depth camera, one 16-bit millimetre TIFF per camera in depthimage/ (docs/or-rig.md)"};

  const fs::path vlm = root / m.vlm;
  inv[CaptureItem::VlmReplies] = {
      !root.empty() &&
          any_view_has(capture, [&](const View& v) { return vlm / v.name / "round_0.txt"; }),
      folder_text(vlm) + "<view>/round_0.txt (none for any of the " + n_views + " views)",
      "produced by the vlm.query node asking a served VLM (graphs/examples/langor_live_vlm.yaml), "
      "or by a VLM of your own writing its raw grounding replies as vlm/<view>/round_<k>.txt "
      "(docs/capture_format.md, docs/vlm_query.md)"};

  const fs::path sam_auto = root / m.sam_auto;
  inv[CaptureItem::SamAutoMasks] = {
      !root.empty() &&
          any_view_has(capture, [&](const View& v) { return sam_auto / (v.name + ".json"); }),
      folder_text(sam_auto) + "<view>.json (none for any of the " + n_views + " views)",
      "produced by SAM's automatic mask generator, one sam_auto/<view>.json per view "
      "(docs/capture_format.md); or let gslift make masks: --set <node>.type=masks.auto"};

  const std::string gt = m.gt.empty() ? std::string(
                                            "capture.yaml's gt: folder (this capture "
                                            "names none)")
                                      : folder_text(root / m.gt);
  const std::string gt_source =
      "ground truth comes from annotations of your own in capture.yaml's gt: folder "
      "(docs/capture_format.md) or from `gslift synth`; without it, run the graph's production "
      "form (graphs/README.md)";
  inv[CaptureItem::GtInstances] = {
      some_view(capture, [](const View& v) { return v.gt_instance.present(); }),
      gt + (m.gt.empty() ? "" : "instance/<view>.png"), gt_source};
  inv[CaptureItem::GtSemantics] = {
      some_view(capture, [](const View& v) { return v.gt_semantic.present(); }),
      gt + (m.gt.empty() ? "" : "semantic/<view>.png"), gt_source};
  inv[CaptureItem::GtClasses] = {!capture.classes.empty(),
                                 gt + (m.gt.empty() ? "" : "classes.yaml"), gt_source};

  inv[CaptureItem::HeldOutViews] = {
      !capture.test_views().empty(),
      "a held-out view among the " + n_views +
          " (capture.yaml held_out:, or ingest.capture's "
          "holdout_every)",
      "hold out every n-th view with --set <capture node>.holdout_every=8, or list them in "
      "capture.yaml's held_out: (docs/capture_format.md)"};
  return inv;
}

}  // namespace gslift
