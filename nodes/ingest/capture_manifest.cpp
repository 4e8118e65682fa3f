#include "nodes/ingest/capture_manifest.hpp"

#include <yaml-cpp/yaml.h>

#include "base/errors.hpp"
#include "base/input_file.hpp"
#include "base/utf8.hpp"

namespace gslift {

CaptureManifest read_capture_manifest(const std::filesystem::path& root, bool allow_outside_paths) {
  CaptureManifest m;
  const auto file = root / "capture.yaml";
  if (!entry_exists(file)) return m;
  const std::string where = file.string();
  require_inside(root, file, allow_outside_paths, "capture.yaml");
  try {
    const YAML::Node y = YAML::Load(read_input_file(file, "capture.yaml"));
    const std::string format = y["format"] ? y["format"].as<std::string>() : "";
    if (format != "gslift.capture/v1")
      throw InputError(where + ": format must be gslift.capture/v1, got '" + printable(format) +
                       "'");
    if (y["name"]) m.name = y["name"].as<std::string>();
    if (y["model"]) m.model = y["model"].as<std::string>();
    if (y["images"]) m.images = y["images"].as<std::string>();
    if (y["rig"]) {
      if (y["model"] || y["depth"])
        throw InputError(where +
                         ": rig: names the views and their depth; it excludes model: "
                         "and depth:");
      m.rig = y["rig"].as<std::string>();
      if (m.rig.empty()) m.rig = ".";
    }
    if (const auto d = y["depth"]) {
      m.depth = d["folder"] ? d["folder"].as<std::string>() : "depth";
      if (d["scale"]) m.depth_scale = d["scale"].as<double>();
      if (!(m.depth_scale > 0)) throw InputError(where + ": depth.scale must be positive");
    }
    if (const auto h = y["held_out"]) {
      m.has_held_out = true;
      m.held_out = h.as<std::vector<std::string>>();
    }
    if (const auto v = y["vlm"]) {
      if (v["folder"]) m.vlm = v["folder"].as<std::string>();
      if (v["rounds"]) m.vlm_rounds = v["rounds"].as<int>();
      if (v["coords"]) {
        try {
          m.vlm_coords =
              parse_enum(v["coords"].as<std::string>(), vlm_coords_names(), "vlm.coords");
        } catch (const std::invalid_argument& e) {
          throw InputError(where + ": " + e.what());
        }
      }
      if (v["input_size"]) {
        const auto s = v["input_size"].as<std::vector<int>>();
        if (s.size() != 2 || s[0] <= 0 || s[1] <= 0)
          throw InputError(where + ": vlm.input_size must be [width, height]");
        m.vlm_input_width = s[0];
        m.vlm_input_height = s[1];
      }
    }
    if (y["sam_box"]) m.sam_box = y["sam_box"].as<std::string>();
    if (y["sam_auto"]) m.sam_auto = y["sam_auto"].as<std::string>();
    if (y["gt"]) m.gt = y["gt"].as<std::string>();
  } catch (const YAML::Exception& e) {
    throw InputError(where + ": " + e.what());
  }
  for (const auto& [key, folder] :
       {std::pair<const char*, const std::filesystem::path*>{"model", &m.model},
        {"rig", &m.rig},
        {"images", &m.images},
        {"depth.folder", &m.depth},
        {"vlm.folder", &m.vlm},
        {"sam_box", &m.sam_box},
        {"sam_auto", &m.sam_auto},
        {"gt", &m.gt}})
    path_inside(root, folder->string(), allow_outside_paths, where + " (" + key + ")");
  return m;
}

}  // namespace gslift
