#include "nodes/ingest/capture_loader.hpp"

#include <set>

#include <yaml-cpp/yaml.h>

#include "base/errors.hpp"
#include "base/input_file.hpp"
#include "nodes/ingest/capture_manifest.hpp"
#include "nodes/ingest/colmap_capture.hpp"
#include "nodes/ingest/nerf_transforms.hpp"
#include "nodes/ingest/or_rig.hpp"
#include "nodes/ingest/rgbd_folders.hpp"

namespace gslift {
namespace {

namespace fs = std::filesystem;

bool has_model(const fs::path& dir) {
  return fs::exists(dir / "cameras.bin") || fs::exists(dir / "cameras.txt");
}

// The first existing <folder>/<stem><ext>, or an empty path. An entry that is there but is not
// a readable file (a directory, a FIFO, a dangling symlink) is an error naming it, not "absent";
// one that points outside the capture `root` is refused (require_inside).
fs::path find_file(const fs::path& root, bool allow_outside, const fs::path& folder,
                   const std::string& stem, std::initializer_list<const char*> exts) {
  for (const char* ext : exts) {
    fs::path p = folder / (stem + ext);
    if (!entry_exists(p)) continue;
    require_inside(root, p, allow_outside, "view file");
    require_regular_file(p, "view file");
    return p;
  }
  return {};
}

void read_classes(const fs::path& root, bool allow_outside, const fs::path& file,
                  Capture& capture) {
  if (!entry_exists(file)) return;
  require_inside(root, file, allow_outside, "classes.yaml");
  try {
    const YAML::Node y = YAML::Load(read_input_file(file, "classes.yaml"));
    if (const auto c = y["classes"])
      for (const auto& kv : c) capture.classes[kv.first.as<int>()] = kv.second.as<std::string>();
    if (const auto i = y["instances"])
      for (const auto& kv : i) capture.instance_class[kv.first.as<int>()] = kv.second.as<int>();
  } catch (const YAML::Exception& e) {
    throw InputError(file.string() + ": " + e.what());
  }
}

// Views of a capture.yaml folder, with its depth prior and ground truth attached.
std::vector<ViewFiles> manifest_views(const fs::path& root, const CaptureManifest& m,
                                      const CaptureOptions& options, Capture& capture) {
  auto views = m.rig.empty()
                   ? read_colmap_views(root / m.model, root / m.images, options, capture.points)
                   : read_or_rig_views(root / m.rig, options.allow_outside_paths);
  const fs::path gt = m.gt.empty() ? fs::path() : root / m.gt;
  const bool out = options.allow_outside_paths;
  for (auto& v : views) {
    if (!m.depth.empty()) {
      v.depth = find_file(root, out, root / m.depth, v.name, {".png", ".tiff", ".tif", ".exr"});
      v.depth_scale = m.depth_scale;
    }
    if (!gt.empty()) {
      v.gt_instance = find_file(root, out, gt / "instance", v.name, {".png"});
      v.gt_semantic = find_file(root, out, gt / "semantic", v.name, {".png"});
      v.gt_depth = find_file(root, out, gt / "depth", v.name, {".tiff", ".tif", ".exr"});
      v.gt_normal = find_file(root, out, gt / "normal", v.name, {".tiff", ".tif", ".exr"});
    }
  }
  if (!gt.empty()) read_classes(root, out, gt / "classes.yaml", capture);
  if (m.has_held_out) {
    std::set<std::string> names(m.held_out.begin(), m.held_out.end());
    for (auto& v : views) v.held_out = names.erase(v.name) > 0;
    if (!names.empty())
      throw InputError((root / "capture.yaml").string() + ": held_out names view '" +
                       *names.begin() + "', which the capture does not have");
  }
  return views;
}

fs::path images_beside(const fs::path& model_dir) {
  const fs::path dir = fs::absolute(model_dir).lexically_normal().parent_path();
  const fs::path up = dir.parent_path() / "images";
  return fs::is_directory(dir / "images") || !fs::is_directory(up) ? dir / "images" : up;
}

std::string folder_name(const fs::path& dir) {
  fs::path p = fs::absolute(dir).lexically_normal();
  if (!p.has_filename()) p = p.parent_path();
  return p.filename().string();
}

std::vector<ViewFiles> detected_views(const fs::path& path, const CaptureOptions& options,
                                      Capture& capture) {
  if (fs::is_regular_file(path) && path.extension() == ".json")
    return read_nerf_transforms(path, options.allow_outside_paths);
  if (!fs::is_directory(path)) throw InputError(path.string() + ": no such capture folder");
  for (const char* model : {"sparse/0", "colmap"})
    if (has_model(path / model))
      return read_colmap_views(path / model, path / "images", options, capture.points);
  if (has_model(path)) return read_colmap_views(path, images_beside(path), options, capture.points);
  for (const char* json : {"transforms.json", "transforms_train.json"})
    if (fs::exists(path / json))
      return read_nerf_transforms(path / json, options.allow_outside_paths);
  if (fs::is_directory(path / "results") && fs::exists(path / "traj.txt"))
    return read_replica_views(path);
  if (fs::exists(path / "camera-intrinsics.txt")) return read_3dmatch_views(path);
  if (is_or_rig_step(path)) return read_or_rig_views(path, options.allow_outside_paths);
  throw InputError(path.string() +
                   ": not a capture; looked for capture.yaml, a COLMAP model (sparse/0/, colmap/ "
                   "or cameras.bin|txt), transforms.json, transforms_train.json, Replica "
                   "(results/ + traj.txt), 3DMatch (camera-intrinsics.txt) and an OR rig time "
                   "step (colorimage/ + camera<N>.json here or in the parent; docs/or-rig.md)");
}

Capture load_capture_files(const fs::path& input, const CaptureOptions& options) {
  if (options.downscale < 1 || options.downscale > kMaxDownscale)
    throw InputError(input.string() + ": downscale must be from 1 to " +
                     std::to_string(kMaxDownscale) + ", got " + std::to_string(options.downscale));
  if (options.train_every < 1)
    throw InputError(input.string() + ": train_every must be at least 1, got " +
                     std::to_string(options.train_every));
  const fs::path path = input.filename() == "capture.yaml" ? input.parent_path() : input;
  Capture capture;
  capture.root = fs::is_regular_file(path) ? path.parent_path() : path;
  capture.allow_outside_paths = options.allow_outside_paths;
  std::vector<ViewFiles> views;
  bool named_held_out = false;
  if (entry_exists(path / "capture.yaml")) {  // a directory or FIFO there is an error naming it
    const CaptureManifest m = read_capture_manifest(path, options.allow_outside_paths);
    capture.name = m.name;
    views = manifest_views(path, m, options, capture);
    named_held_out = m.has_held_out;
  } else {
    views = detected_views(path, options, capture);
  }
  if (capture.name.empty()) capture.name = folder_name(capture.root);
  if (views.empty()) throw InputError(path.string() + ": the capture has no views");
  if (!named_held_out && options.holdout_every > 0)
    for (size_t i = 0; i < views.size(); ++i)
      views[i].held_out = i % static_cast<size_t>(options.holdout_every) == 0;
  for (size_t i = 0; i < views.size(); ++i)
    if (i % static_cast<size_t>(options.train_every) != 0) views[i].held_out = true;
  capture.views = make_views(views, options);
  return capture;
}

}  // namespace

Capture load_capture(const fs::path& input, const CaptureOptions& options) {
  try {
    return load_capture_files(input, options);
  } catch (const fs::filesystem_error& e) {
    // std::filesystem's queries throw on what a hostile capture holds (a symlink loop, a name too
    // long): bad input naming the path, not a node failure with a raw system message.
    throw InputError(e.path1().string() + ": " + e.code().message());
  }
}

const ParamTable<CaptureOptions>& capture_param_table() {
  using O = CaptureOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("holdout_every", &O::holdout_every,
               "hold out every n-th view (NeRF protocol: 8) when capture.yaml names no test "
               "views; 0 = none",
               0)
          .add("train_every", &O::train_every,
               "train on every n-th view alone (index % n == 0); the others are held out too "
               "(scored, never trained on); 1 = all",
               1)
          .add("skip_missing_images", &O::skip_missing_images,
               "COLMAP: leave out images the model lists but the images folder lacks, with a "
               "warning, instead of failing")
          .add("downscale", &O::downscale,
               "integer image downscale on load; intrinsics are scaled to match", 1, kMaxDownscale)
          .add("undistort", &O::undistort,
               "undistort images of cameras with distortion on load, so views are ideal "
               "pinholes; off keeps the images and Camera::distortion as captured")
          .add("undistort_crop", &O::undistort_crop,
               "undistort: crop to the rectangle of valid pixels (COLMAP's undistorter), so no "
               "pixel is black for want of a source; off keeps the captured size")
          .add("allow_outside_paths", &O::allow_outside_paths,
               "follow file names in the capture's files (images.txt, transforms.json, "
               "capture.yaml) that point outside its folder (../, absolute paths, symlinks out); "
               "off refuses them (docs/security.md)");
  return table;
}

}  // namespace gslift
