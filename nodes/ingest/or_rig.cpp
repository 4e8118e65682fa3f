#include "nodes/ingest/or_rig.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <regex>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "base/errors.hpp"
#include "base/input_file.hpp"
#include "base/json_read.hpp"
#include "base/utf8.hpp"
#include "nodes/ingest/k4a_calibration.hpp"
#include "nodes/scene/image_header.hpp"

namespace gslift {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// OpenGL camera axes (y up, z backward) <-> OpenCV's (y down, z forward): the rig's poses are in
// OpenGL axes (4D-OR's loaders flip y and z before projecting).
Eigen::Matrix4d gl_flip() {
  return Eigen::Vector4d(1, -1, -1, 1).asDiagonal();
}

Eigen::Matrix4d rig_matrix_of(const Pose& p) {
  return p.world_to_camera();
}

Pose rig_pose_of(const Eigen::Matrix4d& m) {
  Pose p;
  p.R = m.block<3, 3>(0, 0);
  p.t = m.block<3, 1>(0, 3);
  return p;
}

double rig_number(const json& j, const char* key, const std::string& where) {
  if (!j.is_object() || !j.contains(key) || !j.at(key).is_number())
    throw InputError(where + "." + key + ": expected a number");
  const double v = j.at(key).get<double>();
  if (!std::isfinite(v)) throw InputError(where + "." + key + ": must be finite");
  return v;
}

const json& rig_object(const json& j, const char* key, const std::string& where) {
  if (!j.is_object() || !j.contains(key) || !j.at(key).is_object())
    throw InputError(where + "." + key + ": expected an object");
  return j.at(key);
}

// {"m00", "m10", ...}: the rig's cereal export of an Eigen vector, m<row>0.
std::vector<double> vector_of(const json& j, int n, const std::string& where) {
  std::vector<double> v;
  for (int i = 0; i < n; ++i)
    v.push_back(rig_number(j, ("m" + std::to_string(i) + "0").c_str(), where));
  return v;
}

// A camera from color_parameters / depth_parameters. fov_x and fov_y hold focal lengths in
// pixels (4D-OR's projection code uses them as fx, fy); c_x, c_y are in OpenCV's convention
// (pixel centres at integers, as Azure Kinect's calibration). intrinsics_matrix, when present, is
// stored transposed (m<column><row>) and must agree.
Camera camera_of(const json& j, const std::string& where) {
  Camera c;
  const double w = rig_number(j, "width", where), h = rig_number(j, "height", where);
  if (w != std::floor(w) || h != std::floor(h) || w > 1e9 || h > 1e9)
    throw InputError(where + ": width and height must be whole numbers");
  check_image_size(static_cast<long long>(w), static_cast<long long>(h), where);
  c.width = static_cast<int>(w);
  c.height = static_cast<int>(h);
  c.fx = rig_number(j, "fov_x", where);
  c.fy = rig_number(j, "fov_y", where);
  c.cx = rig_number(j, "c_x", where) + 0.5;
  c.cy = rig_number(j, "c_y", where) + 0.5;
  if (j.contains("intrinsics_matrix")) {
    const std::string k = where + ".intrinsics_matrix";
    const json& m = rig_object(j, "intrinsics_matrix", where);
    const double fx = rig_number(m, "m00", k), fy = rig_number(m, "m11", k),
                 cx = rig_number(m, "m20", k), cy = rig_number(m, "m21", k);
    auto near = [](double a, double b) {
      return std::abs(a - b) <= 1e-6 * std::max(1.0, std::abs(b));
    };
    if (!near(fx, c.fx) || !near(fy, c.fy) || !near(cx, c.cx - 0.5) || !near(cy, c.cy - 0.5))
      throw InputError(k + ": (m00, m11, m20, m21) = (" + std::to_string(fx) + ", " +
                       std::to_string(fy) + ", " + std::to_string(cx) + ", " + std::to_string(cy) +
                       ") disagree with fov_x, fov_y, c_x, c_y (the matrix "
                       "is read transposed, as 4D-OR's loader reads it)");
  }
  // OpenCV's order k1 k2 p1 p2 k3 k4 k5 k6 from radial k1..k6 and tangential p1 p2.
  std::vector<double> radial(6, 0.0), tangential(2, 0.0);
  if (j.contains("radial_distortion"))
    radial = vector_of(rig_object(j, "radial_distortion", where), 6, where + ".radial_distortion");
  if (j.contains("tangential_distortion"))
    tangential = vector_of(rig_object(j, "tangential_distortion", where), 2,
                           where + ".tangential_distortion");
  const std::vector<double> d{radial[0], radial[1], tangential[0], tangential[1],
                              radial[2], radial[3], radial[4],     radial[5]};
  const bool rational = radial[3] != 0 || radial[4] != 0 || radial[5] != 0;
  if (std::any_of(d.begin(), d.end(), [](double x) { return x != 0; }))
    c.distortion.assign(d.begin(), rational ? d.end() : d.begin() + 5);
  check_camera(c, where);
  return c;
}

// {rotation {x, y, z, w}, translation {m00, m10, m20}}: a rigid transform, metres.
Eigen::Matrix4d transform_of(const json& j, const std::string& where) {
  const json& r = rig_object(j, "rotation", where);
  const std::string rw = where + ".rotation";
  Eigen::Quaterniond q(rig_number(r, "w", rw), rig_number(r, "x", rw), rig_number(r, "y", rw),
                       rig_number(r, "z", rw));
  if (std::abs(q.norm() - 1) > 1e-3)
    throw InputError(rw + ": not a unit quaternion (norm " + std::to_string(q.norm()) + ")");
  const std::vector<double> t =
      vector_of(rig_object(j, "translation", where), 3, where + ".translation");
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<3, 3>(0, 0) = q.normalized().toRotationMatrix();
  m.block<3, 1>(0, 3) = Eigen::Vector3d(t[0], t[1], t[2]);
  return m;
}

json parameters_json(const Camera& c) {
  std::vector<double> d = c.distortion;
  if (d.size() > 8)
    throw std::invalid_argument(
        "a rig calibration holds k1..k6, p1, p2; the thin prism s1..s4 "
        "has no field");
  d.resize(8, 0.0);  // k1 k2 p1 p2 k3 k4 k5 k6
  json radial, tangential, k;
  const double radial_values[6] = {d[0], d[1], d[4], d[5], d[6], d[7]};
  for (int i = 0; i < 6; ++i) radial["m" + std::to_string(i) + "0"] = radial_values[i];
  tangential["m00"] = d[2];
  tangential["m10"] = d[3];
  const double K[3][3] = {{c.fx, 0, c.cx - 0.5}, {0, c.fy, c.cy - 0.5}, {0, 0, 1}};
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col)
      k["m" + std::to_string(col) + std::to_string(row)] = K[row][col];
  return {{"width", c.width},
          {"height", c.height},
          {"fov_x", c.fx},
          {"fov_y", c.fy},
          {"c_x", c.cx - 0.5},
          {"c_y", c.cy - 0.5},
          {"intrinsics_matrix", k},
          {"radial_distortion", radial},
          {"tangential_distortion", tangential}};
}

json transform_json(const Eigen::Matrix4d& m) {
  const Eigen::Quaterniond q(Eigen::Matrix3d(m.block<3, 3>(0, 0)));
  return {{"rotation", {{"x", q.x()}, {"y", q.y()}, {"z", q.z()}, {"w", q.w()}}},
          {"translation", {{"m00", m(0, 3)}, {"m10", m(1, 3)}, {"m20", m(2, 3)}}}};
}

const std::regex& camera_file_pattern() {
  static const std::regex re("(camera[0-9]+)\\.json");
  return re;
}

// camera<N>.json files of `dir`, by camera name (sorted).
std::map<std::string, fs::path> camera_files(const fs::path& dir) {
  std::map<std::string, fs::path> out;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return out;
  for (const auto& e : fs::directory_iterator(dir)) {
    std::smatch m;
    const std::string file = e.path().filename().string();
    if (std::regex_match(file, m, camera_file_pattern())) out[m[1]] = e.path();
  }
  return out;
}

fs::path calibration_folder(const fs::path& step) {
  if (!camera_files(step).empty()) return step;
  fs::path p = fs::absolute(step).lexically_normal();
  if (!p.has_filename()) p = p.parent_path();  // "step/." normalises to "step/"
  return p.parent_path();
}

// `<camera>_<kind>-<index>.<ext>` files of `dir` by camera; several per camera are kept, so the
// caller can say which time steps it found.
std::map<std::string, std::vector<fs::path>> rig_frames(const fs::path& dir,
                                                        const std::string& kind,
                                                        const std::string& extensions) {
  std::map<std::string, std::vector<fs::path>> out;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return out;
  const std::regex re("(camera[0-9]+)_" + kind + "-([^/]+)\\.(" + extensions + ")");
  for (const auto& e : fs::directory_iterator(dir)) {
    std::smatch m;
    const std::string file = e.path().filename().string();
    if (std::regex_match(file, m, re)) out[m[1]].push_back(e.path());
  }
  for (auto& [camera, files] : out) std::sort(files.begin(), files.end());
  return out;
}

}  // namespace

namespace {

json read_rig_json(const fs::path& file, const char* what) {
  try {
    return parse_json(read_input_file(file, what));
  } catch (const json::exception& e) {
    throw InputError(file.string() + ": " + e.what());
  }
}

// The depth camera's camera-to-world of camera_pose (OpenGL axes, metres) in `v`.
Eigen::Matrix4d depth_camera_to_world(const json& v, const std::string& base) {
  return transform_of(rig_object(v, "camera_pose", base), base + ".camera_pose");
}

fs::path or_rig_pose_file(const fs::path& calibration) {
  return calibration.parent_path() / (calibration.stem().string() + "_pose.json");
}

bool is_or_rig_k4a_calibration(const fs::path& file) {
  return is_k4a_calibration(read_rig_json(file, "rig camera calibration"));
}

}  // namespace

OrRigCamera read_or_rig_camera(const fs::path& file) {
  const std::string where = file.string();
  const json root = read_rig_json(file, "rig camera calibration");
  const json& v = rig_object(root, "value0", where);
  const std::string base = where + ": value0";
  OrRigCamera c;
  c.colour = camera_of(rig_object(v, "color_parameters", base), base + ".color_parameters");
  if (v.contains("depth_parameters"))
    c.depth = camera_of(rig_object(v, "depth_parameters", base), base + ".depth_parameters");
  // camera_pose is the depth camera's camera-to-world and color2depth_transform takes colour-frame
  // points into the depth frame (4D-OR: "Extrinsics were given for the depth camera, convert
  // them to color camera"), both in OpenGL axes.
  const Eigen::Matrix4d depth_c2w = depth_camera_to_world(v, base);
  const Eigen::Matrix4d colour_to_depth =
      transform_of(rig_object(v, "color2depth_transform", base), base + ".color2depth_transform");
  const Eigen::Matrix4d F = gl_flip();
  c.colour_pose = Pose::from_camera_to_world(depth_c2w * colour_to_depth * F);
  c.depth_to_colour = rig_pose_of(F * colour_to_depth.inverse() * F);
  return c;
}

OrRigCamera read_or_rig_k4a_camera(const fs::path& file, cv::Size colour,
                                   std::optional<cv::Size> depth) {
  const std::string where = file.string();
  const K4aCalibration k =
      parse_k4a_calibration(read_rig_json(file, "Azure Kinect calibration"), where);
  OrRigCamera c;
  c.colour = k4a_colour_camera(k.colour, colour.width, colour.height,
                               where + ": colour camera (CALIBRATION_CameraLocationPV0)");
  if (depth)
    c.depth = k4a_depth_camera(k.depth, depth->width, depth->height,
                               where + ": depth camera (CALIBRATION_CameraLocationD0)");
  c.depth_to_colour = k4a_depth_to_colour(k);
  // The raw export places the sensors relative to the depth camera only. The rig pose, as
  // camera0X.json's camera_pose (the depth camera's camera-to-world, OpenGL axes), is read from
  // camera<N>_pose.json; without it the depth camera (OpenCV axes) is the world, as in the SDK.
  Eigen::Matrix4d depth_c2w = Eigen::Matrix4d::Identity();
  const fs::path pose_file = or_rig_pose_file(file);
  std::error_code ec;
  if (fs::exists(pose_file, ec)) {
    const std::string base = pose_file.string() + ": value0";
    depth_c2w = depth_camera_to_world(rig_object(read_rig_json(pose_file, "rig camera pose"),
                                                 "value0", pose_file.string()),
                                      base) *
                gl_flip();
  }
  c.colour_pose =
      Pose::from_camera_to_world(depth_c2w * rig_matrix_of(c.depth_to_colour).inverse());
  return c;
}

std::string or_rig_camera_json(const OrRigCamera& c) {
  const Eigen::Matrix4d F = gl_flip();
  const Eigen::Matrix4d colour_c2w_gl = rig_matrix_of(c.colour_pose).inverse() * F;
  const Eigen::Matrix4d colour_to_depth = F * rig_matrix_of(c.depth_to_colour).inverse() * F;
  json v;
  v["color_parameters"] = parameters_json(c.colour);
  if (c.depth) v["depth_parameters"] = parameters_json(*c.depth);
  v["camera_pose"] = transform_json(colour_c2w_gl * colour_to_depth.inverse());
  v["color2depth_transform"] = transform_json(colour_to_depth);
  return json{{"value0", v}}.dump(2);
}

bool is_or_rig_step(const fs::path& folder) {
  std::error_code ec;
  return fs::is_directory(folder / "colorimage", ec) &&
         !camera_files(calibration_folder(folder)).empty();
}

std::vector<ViewFiles> read_or_rig_views(const fs::path& folder, bool allow_outside) {
  const fs::path calibration = calibration_folder(folder);
  const auto cameras = camera_files(calibration);
  if (cameras.empty())
    throw InputError(folder.string() + ": no camera<N>.json in it or in its parent");
  const auto colour = rig_frames(folder / "colorimage", "colorimage", "jpg|jpeg|png");
  const auto depth = rig_frames(folder / "depthimage", "depthimage", "tiff|tif|png");
  for (const auto& [camera, files] : colour)
    if (!cameras.count(camera))
      throw InputError(files.front().string() + ": no calibration " + camera + ".json in " +
                       calibration.string());
  std::vector<ViewFiles> views;
  for (const auto& [name, file] : cameras) {
    const auto found = colour.find(name);
    if (found == colour.end()) continue;  // this camera has no frame at this time step
    const std::vector<fs::path>& rgb = found->second;
    if (rgb.size() > 1)
      throw InputError((folder / "colorimage").string() + ": " + std::to_string(rgb.size()) +
                       " frames of " + name + " (" + rgb[0].filename().string() + ", " +
                       rgb[1].filename().string() +
                       ", ...): a capture is one time step; put each time step in a folder of "
                       "its own (docs/or-rig.md)");
    ViewFiles v;
    v.name = name;
    v.rgb = require_inside(folder, rgb[0], allow_outside, "rig colour frame");
    require_regular_file(v.rgb, "rig colour frame");
    const auto d = depth.find(name);
    if (d != depth.end()) {
      // The depth frame of the colour frame's time step: the same index after the kind.
      const std::string index =
          rgb[0].stem().string().substr(name.size() + std::string("_colorimage-").size());
      for (const fs::path& p : d->second)
        if (p.stem().string() == name + "_depthimage-" + index) v.depth = p;
      if (v.depth.empty())
        throw InputError((folder / "depthimage").string() + ": no " + name + "_depthimage-" +
                         index + " beside " + rgb[0].filename().string() + " (found " +
                         d->second.front().filename().string() + ")");
      require_inside(folder, v.depth, allow_outside, "rig depth frame");
      require_regular_file(v.depth, "rig depth frame");
    }
    OrRigCamera cam;
    if (is_or_rig_k4a_calibration(file)) {
      // Azure Kinect's raw calibration: the frames' sizes name the colour and depth modes.
      if (cameras.size() > 1 && !fs::exists(or_rig_pose_file(file)))
        throw InputError(file.string() +
                         ": an Azure Kinect calibration places the camera only relative to its "
                         "own depth sensor; a rig of " +
                         std::to_string(cameras.size()) + " cameras needs its pose in " +
                         or_rig_pose_file(file).string() + " (docs/or-rig.md)");
      auto frame_size = [](const fs::path& p, const char* what) {
        const ImageHeader h = read_image_header(p);
        check_image_header(h, p.string() + " (" + what + ")");
        return cv::Size(static_cast<int>(h.width), static_cast<int>(h.height));
      };
      std::optional<cv::Size> depth_size;
      if (!v.depth.empty()) depth_size = frame_size(v.depth, "rig depth frame");
      cam = read_or_rig_k4a_camera(file, frame_size(v.rgb, "rig colour frame"), depth_size);
    } else {
      cam = read_or_rig_camera(file);
    }
    v.camera = cam.colour;
    v.pose = cam.colour_pose;
    if (!v.depth.empty()) {
      v.depth_scale = 1000;  // 16-bit millimetres, as the Azure Kinect's DEPTH16
      v.depth_sensor = DepthSensor{cam.depth ? *cam.depth : cam.colour, cam.depth_to_colour};
      if (!cam.depth) {
        // Registered to colour already: the same camera, at the depth file's resolution.
        v.depth_sensor->depth_to_colour = Pose();
        v.depth_sensor_fits_file = true;
      }
    }
    views.push_back(std::move(v));
  }
  if (views.empty())
    throw InputError(folder.string() +
                     ": no colour frame colorimage/camera<N>_colorimage-<index>"
                     ".{jpg,png} of a calibrated camera");
  return views;
}

}  // namespace gslift
