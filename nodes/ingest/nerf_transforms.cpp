#include "nodes/ingest/nerf_transforms.hpp"

#include <cmath>
#include <optional>
#include <set>

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "base/errors.hpp"
#include "base/input_file.hpp"
#include "base/json_read.hpp"
#include "nodes/scene/image_io.hpp"

namespace gslift {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The frame's value of `key`, else the file's, else nothing.
std::optional<double> number(const json& frame, const json& top, const char* key,
                             const std::string& where) {
  for (const json* j : {&frame, &top}) {
    auto it = j->find(key);
    if (it == j->end()) continue;
    if (!it->is_number()) throw InputError(where + ": '" + key + "' must be a number");
    return it->get<double>();
  }
  return std::nullopt;
}

std::optional<fs::path> find_image(const fs::path& base) {
  if (base.has_extension() && fs::is_regular_file(base)) return base;
  for (const char* ext : {".png", ".jpg", ".jpeg", ".PNG", ".JPG", ".JPEG"}) {
    fs::path p = base;
    p += ext;
    if (fs::is_regular_file(p)) return p;
  }
  return std::nullopt;
}

Eigen::Matrix4d matrix_of(const json& m, const std::string& where) {
  if (!m.is_array() || (m.size() != 4 && m.size() != 3))
    throw InputError(where + ": transform_matrix must be a 4x4 (or 3x4) array");
  Eigen::Matrix4d c2w = Eigen::Matrix4d::Identity();
  for (size_t r = 0; r < m.size(); ++r) {
    if (!m[r].is_array() || m[r].size() != 4)
      throw InputError(where + ": transform_matrix row " + std::to_string(r) +
                       " must hold 4 numbers");
    for (size_t c = 0; c < 4; ++c) {
      if (!m[r][c].is_number()) throw InputError(where + ": transform_matrix holds a non-number");
      c2w(r, c) = m[r][c].get<double>();
    }
  }
  if (!c2w.allFinite()) throw InputError(where + ": transform_matrix holds NaN or Inf");
  return c2w;
}

}  // namespace

Pose pose_from_opengl_c2w(const Eigen::Matrix4d& c2w) {
  Eigen::Matrix4d cv = c2w;
  cv.col(1) *= -1;  // y up -> y down
  cv.col(2) *= -1;  // looking down -z -> looking down +z
  return Pose::from_camera_to_world(cv);
}

std::vector<ViewFiles> read_nerf_transforms(const fs::path& json_file, bool allow_outside_paths) {
  const std::string text = read_input_file(json_file, "transforms file");
  json top;
  try {
    top = parse_json(text);
  } catch (const json::exception& e) {
    throw InputError(json_file.string() + ": invalid JSON: " + e.what());
  }
  if (!top.is_object() || !top.contains("frames") || !top["frames"].is_array())
    throw InputError(json_file.string() + ": no 'frames' list");

  const fs::path dir = json_file.parent_path();
  std::vector<ViewFiles> views;
  std::set<std::string> names;
  int missing = 0;
  cv::Size probed;  // size of the first image, for files without w/h
  const json& frames = top["frames"];
  for (size_t i = 0; i < frames.size(); ++i) {
    const json& f = frames[i];
    const std::string where = json_file.string() + " frame " + std::to_string(i);
    if (!f.is_object() || !f.contains("file_path") || !f["file_path"].is_string())
      throw InputError(where + ": needs a 'file_path' string");
    const auto rgb =
        find_image(path_inside(dir, f["file_path"].get<std::string>(), allow_outside_paths, where));
    if (!rgb) {
      ++missing;
      continue;
    }
    ViewFiles v;
    v.rgb = *rgb;
    v.name = rgb->stem().string();
    if (!names.insert(v.name).second)
      throw InputError(where + ": image name '" + v.name + "' appears twice");
    v.pose = pose_from_opengl_c2w(matrix_of(f.value("transform_matrix", json()), where));

    Camera& c = v.camera;
    auto w = number(f, top, "w", where), h = number(f, top, "h", where);
    if (!w || !h) {
      // Decoded once: frames share the size (each image is checked against it when loaded).
      if (probed.empty()) {
        probed = read_image(*rgb).size();
      }
      w = probed.width;
      h = probed.height;
    }
    // Checked before narrowing to int: 1e20 would be undefined behaviour, 1e9 a huge allocation.
    if (!(std::abs(*w) < 1e15 && std::abs(*h) < 1e15 && *w == std::floor(*w) &&
          *h == std::floor(*h)))
      throw InputError(where + ": image size must be whole numbers, got " + std::to_string(*w) +
                       " x " + std::to_string(*h));
    check_image_size(static_cast<long long>(*w), static_cast<long long>(*h), where);
    c.width = static_cast<int>(*w);
    c.height = static_cast<int>(*h);
    auto fx = number(f, top, "fl_x", where);
    if (!fx) {
      const auto ax = number(f, top, "camera_angle_x", where);
      if (!ax) throw InputError(where + ": needs fl_x or camera_angle_x");
      fx = 0.5 * c.width / std::tan(0.5 * *ax);
    }
    auto fy = number(f, top, "fl_y", where);
    if (!fy) {
      const auto ay = number(f, top, "camera_angle_y", where);
      fy = ay ? 0.5 * c.height / std::tan(0.5 * *ay) : *fx;
    }
    c.fx = *fx;
    c.fy = *fy;
    c.cx = number(f, top, "cx", where).value_or(0.5 * c.width);
    c.cy = number(f, top, "cy", where).value_or(0.5 * c.height);
    // nerfstudio names its model; only the OpenCV radial-tangential one maps onto Camera.
    const json& model_of = f.contains("camera_model") ? f : top;
    if (model_of.contains("camera_model")) {
      const std::string model = model_of["camera_model"].is_string()
                                    ? model_of["camera_model"].get<std::string>()
                                    : std::string("?");
      if (model != "OPENCV" && model != "PINHOLE" && model != "SIMPLE_PINHOLE")
        throw InputError(where + ": camera_model '" + model +
                         "' is not supported (OPENCV, PINHOLE or SIMPLE_PINHOLE)");
    }
    std::vector<double> d;
    for (const char* k : {"k1", "k2", "p1", "p2"})
      d.push_back(number(f, top, k, where).value_or(0));
    if (const auto k3 = number(f, top, "k3", where); k3 && *k3 != 0) d.push_back(*k3);
    for (double x : d)
      if (x != 0) c.distortion = d;
    check_camera(c, where);

    if (f.contains("depth_file_path") && f["depth_file_path"].is_string()) {
      v.depth =
          path_inside(dir, f["depth_file_path"].get<std::string>(), allow_outside_paths, where);
      v.depth_scale = 1000;
    }
    views.push_back(std::move(v));
  }
  if (missing > 0)
    spdlog::warn("{}: skipped {} of {} frames whose image is absent", json_file.string(), missing,
                 frames.size());
  return views;
}

}  // namespace gslift
