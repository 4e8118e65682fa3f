#include "nodes/ingest/capture_annotations.hpp"

#include <opencv2/imgproc.hpp>

#include "base/errors.hpp"
#include "base/input_file.hpp"
#include "nodes/ingest/capture_manifest.hpp"
#include "nodes/ingest/sam_masks.hpp"
#include "nodes/ingest/vlm_reply.hpp"
#include "nodes/scene/image_io.hpp"

namespace gslift {
namespace {

namespace fs = std::filesystem;

fs::path round_file(const fs::path& folder, const std::string& view, int k, const char* ext) {
  return folder / view / ("round_" + std::to_string(k) + ext);
}

// A mask decoded at the resolution SAM saw, brought to the view's grid. The only size change
// allowed is the ingest downscale (same rounding as Camera::scaled).
cv::Mat1b to_view_grid(const cv::Mat1b& m, const Camera& cam, const std::string& where) {
  if (m.cols == cam.width && m.rows == cam.height) return m;
  const int k = static_cast<int>(std::lround(static_cast<double>(m.cols) / cam.width));
  if (k < 1 || static_cast<int>(m.cols / double(k) + 0.5) != cam.width ||
      static_cast<int>(m.rows / double(k) + 0.5) != cam.height)
    throw InputError(where + ": mask is " + std::to_string(m.cols) + " x " +
                     std::to_string(m.rows) + ", but the view is " + std::to_string(cam.width) +
                     " x " + std::to_string(cam.height));
  cv::Mat1b out;
  cv::resize(m, out, cv::Size(cam.width, cam.height), 0, 0, cv::INTER_NEAREST);
  return out;
}

// Width of the image file the VLM was shown, for `pixels` coordinates after a downscale.
double pixel_scale(const View& v) {
  if (v.rgb.path().empty()) return 1;
  const cv::Mat full = read_image(v.rgb.path());
  return static_cast<double>(v.camera.width) / full.cols;
}

}  // namespace

BoxSet load_vlm_boxes(const Capture& capture, const VlmLoadOptions& options, int* rounds_unparsed) {
  const CaptureManifest m = read_capture_manifest(capture.root, capture.allow_outside_paths);
  const fs::path folder = capture.root / m.vlm;
  VlmFrame frame;
  frame.coords = options.coords == VlmCoords::Auto ? m.vlm_coords : options.coords;
  frame.input_width = m.vlm_input_width;
  frame.input_height = m.vlm_input_height;
  BoxSet set;
  int unparsed = 0;
  for (const View& v : capture.views) {
    std::vector<std::string> replies;
    for (int k = 0; options.rounds == 0 || k < options.rounds; ++k) {
      const fs::path file = round_file(folder, v.name, k, ".txt");
      if (!entry_exists(file)) {
        if (options.rounds == 0) break;
        throw InputError(file.string() + ": VLM reply of round " + std::to_string(k) +
                         " is missing (" + std::to_string(options.rounds) + " rounds asked)");
      }
      require_inside(capture.root, file, capture.allow_outside_paths, "VLM reply");
      replies.push_back(read_input_file(file));
    }
    frame.image_width = v.camera.width;
    frame.image_height = v.camera.height;
    if (frame.coords == VlmCoords::Pixels && !replies.empty()) frame.pixel_scale = pixel_scale(v);
    ViewReplies parsed = parse_view_replies(v.name, replies, frame, [&](int k) {
      return round_file(folder, v.name, k, ".txt").string();
    });
    unparsed += parsed.unparsed;
    set.views.push_back(std::move(parsed.boxes));
  }
  if (rounds_unparsed) *rounds_unparsed = unparsed;
  return set;
}

MaskSet load_sam_box_masks(const Capture& capture, const BoxSet& boxes) {
  if (capture.root.empty()) {  // built in memory: no files beside it
    MaskSet none;
    for (const ViewBoxes& vb : boxes.views) none.views.push_back({vb.view, {}});
    return none;
  }
  const CaptureManifest m = read_capture_manifest(capture.root, capture.allow_outside_paths);
  const fs::path folder = capture.root / m.sam_box;
  MaskSet set;
  for (const ViewBoxes& vb : boxes.views) {
    const int vi = capture.find_view(vb.view);
    if (vi < 0) throw InputError(folder.string() + ": boxes name unknown view '" + vb.view + "'");
    const Camera& cam = capture.views[vi].camera;
    ViewMasks vm;
    vm.view = vb.view;
    for (int k = 0; k < vb.rounds; ++k) {
      const fs::path file = round_file(folder, vb.view, k, ".json");
      if (!entry_exists(file)) continue;
      require_inside(capture.root, file, capture.allow_outside_paths, "SAM box record");
      auto masks = parse_sam_box_masks(read_input_file(file), file.string());
      for (size_t j = 0; j < masks.size(); ++j) {
        if (!masks[j]) continue;
        for (size_t b = 0; b < vb.boxes.size(); ++b) {
          if (vb.boxes[b].round != k || vb.boxes[b].source_index != static_cast<int>(j)) continue;
          Mask mask = std::move(*masks[j]);
          mask.pixels = to_view_grid(mask.pixels, cam, file.string());
          mask.box_index = static_cast<int>(b);
          mask.label = vb.boxes[b].label;
          vm.masks.push_back(std::move(mask));
          break;
        }
      }
    }
    set.views.push_back(std::move(vm));
  }
  return set;
}

MaskSet load_sam_auto_masks(const Capture& capture) {
  const CaptureManifest m = read_capture_manifest(capture.root, capture.allow_outside_paths);
  const fs::path folder = capture.root / m.sam_auto;
  MaskSet set;
  for (const View& v : capture.views) {
    ViewMasks vm;
    vm.view = v.name;
    const fs::path file = folder / (v.name + ".json");
    if (entry_exists(file)) {
      require_inside(capture.root, file, capture.allow_outside_paths, "SAM record");
      vm.masks = parse_sam_auto_masks(read_input_file(file), file.string());
      for (Mask& mask : vm.masks) mask.pixels = to_view_grid(mask.pixels, v.camera, file.string());
    }
    set.views.push_back(std::move(vm));
  }
  return set;
}

const ParamTable<VlmLoadOptions>& vlm_load_param_table() {
  using O = VlmLoadOptions;
  static const EnumNames<VlmCoords> coords = [] {
    EnumNames<VlmCoords> names = {{VlmCoords::Auto, "auto"}};
    for (const auto& entry : vlm_coords_names()) names.push_back(entry);
    return names;
  }();
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("coords", &O::coords, coords,
               "the VLM's coordinate space; auto = capture.yaml vlm.coords (norm1000 without one)")
          .add("rounds", &O::rounds, "rounds to read per view; 0 = all found, n = exactly 0..n-1",
               0);
  return table;
}

}  // namespace gslift
