#include "nodes/ingest/k4a_calibration.hpp"

#include <array>
#include <cmath>

#include "base/errors.hpp"

namespace gslift {

namespace {

using nlohmann::json;

double k4a_number(const json& j, const std::string& where) {
  if (!j.is_number()) throw InputError(where + ": expected a number");
  const double v = j.get<double>();
  if (!std::isfinite(v)) throw InputError(where + ": must be finite");
  return v;
}

const json& k4a_field(const json& j, const char* key, const std::string& where) {
  if (!j.is_object() || !j.contains(key)) throw InputError(where + ": no field " + key);
  return j.at(key);
}

std::vector<double> k4a_numbers(const json& j, size_t at_least, const std::string& where) {
  if (!j.is_array() || j.size() < at_least)
    throw InputError(where + ": expected an array of at least " + std::to_string(at_least) +
                     " numbers");
  std::vector<double> v;
  for (size_t i = 0; i < j.size(); ++i)
    v.push_back(k4a_number(j[i], where + "[" + std::to_string(i) + "]"));
  return v;
}

int k4a_size(const json& j, const char* key, const std::string& where) {
  const double v = k4a_number(k4a_field(j, key, where), where + "." + key);
  if (v != std::floor(v) || v < 1 || v > 1e5)
    throw InputError(where + "." + key + ": expected a whole number of pixels");
  return static_cast<int>(v);
}

K4aSensor k4a_sensor(const json& camera, const std::string& where) {
  K4aSensor s;
  s.sensor_width = k4a_size(camera, "SensorWidth", where);
  s.sensor_height = k4a_size(camera, "SensorHeight", where);
  const std::string wi = where + ".Intrinsics";
  const json& intrinsics = k4a_field(camera, "Intrinsics", where);
  const json& type = k4a_field(intrinsics, "ModelType", wi);
  // Rational6KT has p1, p2 without OpenCV's factor 2 on the x*y terms (intrinsic_transformation.c);
  // Theta and Polynomial3K are older models the SDK itself no longer projects with.
  if (!type.is_string() || type.get<std::string>() != "CALIBRATION_LensDistortionModelBrownConrady")
    throw InputError(wi + ".ModelType: " + type.dump() +
                     " is not CALIBRATION_LensDistortionModelBrownConrady, the model of every "
                     "retail Azure Kinect and the one OpenCV's rational model equals");
  const double count =
      k4a_number(k4a_field(intrinsics, "ModelParameterCount", wi), wi + ".ModelParameterCount");
  if (count < 14)
    throw InputError(wi + ".ModelParameterCount: " + std::to_string(count) +
                     ", Brown-Conrady has 14 (cx cy fx fy k1..k6 codx cody p2 p1)");
  const std::vector<double> p =
      k4a_numbers(k4a_field(intrinsics, "ModelParameters", wi), 14, wi + ".ModelParameters");
  // k4a_calibration_intrinsic_parameters_t's order: cx cy fx fy k1 k2 k3 k4 k5 k6 codx cody p2 p1.
  s.cx = p[0];
  s.cy = p[1];
  s.fx = p[2];
  s.fy = p[3];
  if (!(s.fx > 0) || !(s.fy > 0))
    throw InputError(wi + ".ModelParameters: fx, fy (the third and fourth) must be positive");
  if (p[10] != 0 || p[11] != 0)
    throw InputError(wi + ".ModelParameters: centre of distortion codx, cody = (" +
                     std::to_string(p[10]) + ", " + std::to_string(p[11]) +
                     ") is not (0, 0), which OpenCV's model cannot hold (Brown-Conrady sets it 0)");
  const double k1 = p[4], k2 = p[5], k3 = p[6], k4 = p[7], k5 = p[8], k6 = p[9];
  const double p2 = p[12], p1 = p[13];
  s.distortion = {k1, k2, p1, p2, k3, k4, k5, k6};
  if (k1 == 0 && k2 == 0 && k3 == 0 && k4 == 0 && k5 == 0 && k6 == 0 && p1 == 0 && p2 == 0)
    s.distortion.clear();

  const std::string wr = where + ".Rt";
  const json& rt = k4a_field(camera, "Rt", where);
  const std::vector<double> r = k4a_numbers(k4a_field(rt, "Rotation", wr), 9, wr + ".Rotation");
  const std::vector<double> t =
      k4a_numbers(k4a_field(rt, "Translation", wr), 3, wr + ".Translation");
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col) s.world_to_sensor.R(row, col) = r[3 * row + col];
  // The file holds 32-bit floats: orthonormal to their precision, not to a double's.
  const double off =
      (s.world_to_sensor.R * s.world_to_sensor.R.transpose() - Eigen::Matrix3d::Identity())
          .cwiseAbs()
          .maxCoeff();
  if (off > 1e-4 || s.world_to_sensor.R.determinant() < 0)
    throw InputError(wr +
                     ".Rotation: not a rotation (row-major 3 x 3; R R^T is off the identity "
                     "by " +
                     std::to_string(off) + ")");
  s.world_to_sensor.t = Eigen::Vector3d(t[0], t[1], t[2]);
  return s;
}

// A mode of the SDK's table: the calibration scaled to `binned`, then cropped by `crop` to the
// output size.
struct K4aMode {
  int width, height;  // output image
  int binned_width, binned_height;
  int crop_x, crop_y;
};

// mode_specific_calibration.c, in gslift's pixel convention: the raw intrinsics are 0-cornered
// like gslift's (the SDK subtracts 0.5 only to reach OpenCV's centred convention).
Camera k4a_mode_camera(double cx, double cy, double fx, double fy, const K4aMode& m) {
  Camera c;
  c.width = m.width;
  c.height = m.height;
  c.fx = fx * m.binned_width;
  c.fy = fy * m.binned_height;
  c.cx = cx * m.binned_width - m.crop_x;
  c.cy = cy * m.binned_height - m.crop_y;
  return c;
}

}  // namespace

bool is_k4a_calibration(const json& root) {
  return root.is_object() && root.contains("CalibrationInformation");
}

K4aCalibration parse_k4a_calibration(const json& root, const std::string& where) {
  const std::string wc = where + ": CalibrationInformation.Cameras";
  const json& cameras = k4a_field(k4a_field(root, "CalibrationInformation", where + ": root"),
                                  "Cameras", where + ": CalibrationInformation");
  if (!cameras.is_array()) throw InputError(wc + ": expected an array");
  std::optional<K4aSensor> depth, colour;
  for (size_t i = 0; i < cameras.size(); ++i) {
    const std::string wi = wc + "[" + std::to_string(i) + "]";
    const json& location = k4a_field(cameras[i], "Location", wi);
    if (!location.is_string()) throw InputError(wi + ".Location: expected a string");
    // The first camera of a location wins, as the SDK's get_camera_calibration takes it.
    if (location == "CALIBRATION_CameraLocationD0" && !depth)
      depth = k4a_sensor(cameras[i], wi);
    else if (location == "CALIBRATION_CameraLocationPV0" && !colour)
      colour = k4a_sensor(cameras[i], wi);
  }
  if (!depth) throw InputError(wc + ": no camera with Location CALIBRATION_CameraLocationD0");
  if (!colour) throw InputError(wc + ": no camera with Location CALIBRATION_CameraLocationPV0");
  K4aCalibration c{*depth, *colour};
  const double baseline = k4a_depth_to_colour(c).t.norm();
  if (baseline > 0.5)
    throw InputError(
        wc + ": the depth and colour cameras are " + std::to_string(baseline) +
        " apart; Rt.Translation is in metres in the raw export (the SDK converts it to "
        "millimetres on load), and both sensors sit in one 10 cm device");
  return c;
}

Camera k4a_colour_camera(const K4aSensor& s, int width, int height, const std::string& where) {
  double cx = s.cx, cy = s.cy, fx = s.fx, fy = s.fy;
  if (s.sensor_width * 9 / 16 == s.sensor_height) {
    // A legacy 16:9 calibration: the SDK maps it onto the 4:3 sensor first, 4096 x 2304 moved
    // down by 384 rows into 4096 x 3072, still normalised.
    cy = (cy * 2304 + 384) / 3072;
    fy = fy * 2304 / 3072;
  } else if (s.sensor_width * 3 / 4 != s.sensor_height) {
    throw InputError(where + ": the colour sensor is " + std::to_string(s.sensor_width) + " x " +
                     std::to_string(s.sensor_height) +
                     ", neither 4:3 nor 16:9, which the Azure Kinect SDK's modes need");
  }
  static const std::array<K4aMode, 6> modes{{{1280, 720, 1280, 960, 0, 120},
                                             {1920, 1080, 1920, 1440, 0, 180},
                                             {2560, 1440, 2560, 1920, 0, 240},
                                             {2048, 1536, 2048, 1536, 0, 0},
                                             {3840, 2160, 3840, 2880, 0, 360},
                                             {4096, 3072, 4096, 3072, 0, 0}}};
  for (const K4aMode& m : modes)
    if (m.width == width && m.height == height) {
      Camera c = k4a_mode_camera(cx, cy, fx, fy, m);
      c.distortion = s.distortion;
      check_camera(c, where);
      return c;
    }
  throw InputError(where + ": colour frames are " + std::to_string(width) + " x " +
                   std::to_string(height) +
                   ", not the size of an Azure Kinect colour mode (1280 x 720, 1920 x 1080, "
                   "2560 x 1440, 2048 x 1536, 3840 x 2160, 4096 x 3072)");
}

std::optional<Camera> k4a_depth_camera(const K4aSensor& s, int width, int height,
                                       const std::string& where) {
  static const std::array<K4aMode, 4> modes{{{320, 288, 512, 512, 96, 90},
                                             {640, 576, 1024, 1024, 192, 180},
                                             {512, 512, 512, 512, 0, 0},
                                             {1024, 1024, 1024, 1024, 0, 0}}};
  for (const K4aMode& m : modes)
    if (m.width == width && m.height == height) {
      // transformation_get_mode_specific_depth_camera_calibration refuses any other sensor.
      if (s.sensor_width != 1024 || s.sensor_height != 1024)
        throw InputError(where + ": the depth sensor is " + std::to_string(s.sensor_width) + " x " +
                         std::to_string(s.sensor_height) +
                         "; the Azure Kinect SDK's depth modes are defined for 1024 x 1024");
      Camera c = k4a_mode_camera(s.cx, s.cy, s.fx, s.fy, m);
      c.distortion = s.distortion;
      check_camera(c, where);
      return c;
    }
  return std::nullopt;
}

Pose k4a_depth_to_colour(const K4aCalibration& c) {
  // extrinsics[source][target] = world_to_target * inverse(world_to_source).
  const Pose& d = c.depth.world_to_sensor;
  const Pose& k = c.colour.world_to_sensor;
  Pose p;
  p.R = k.R * d.R.transpose();
  p.t = k.t - p.R * d.t;
  return p;
}

}  // namespace gslift
