// Azure Kinect's raw calibration: the JSON that k4a_device_get_raw_calibration returns and that
// k4arecorder stores as the `calibration.json` attachment of a recording (Azure-Kinect-Sensor-SDK
// src/calibration/calibration.c reads it; src/transformation/mode_specific_calibration.c turns it
// into the intrinsics of a camera mode). docs/or-rig.md says what is read and what is inferred.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "nodes/scene/camera.hpp"

namespace gslift {

// One sensor of the device as the raw file stores it.
struct K4aSensor {
  int sensor_width = 0, sensor_height = 0;  // the resolution the intrinsics are normalised by
  // Principal point and focal lengths divided by the sensor size, (0, 0) at the top-left corner
  // of the top-left pixel (the SDK's "unitized and 0-cornered").
  double cx = 0, cy = 0, fx = 0, fy = 0;
  // OpenCV's k1 k2 p1 p2 k3 k4 k5 k6, reordered from the file's cx cy fx fy k1..k6 codx cody p2 p1.
  std::vector<double> distortion;
  Pose world_to_sensor;  // Rt, translation in metres; the SDK's world is the depth camera
};

struct K4aCalibration {
  K4aSensor depth;   // Location CALIBRATION_CameraLocationD0
  K4aSensor colour;  // Location CALIBRATION_CameraLocationPV0
};

// Whether a parsed JSON document is a raw k4a calibration (has CalibrationInformation).
bool is_k4a_calibration(const nlohmann::json& root);

// Reads CalibrationInformation.Cameras[] of the depth and colour sensors. Throws InputError naming
// `where` and the field for a missing or malformed field, a model other than Brown-Conrady (the
// deprecated Rational6KT drops the tangential factor 2 that OpenCV has), a centre of distortion
// (codx, cody) off zero, which OpenCV's model cannot hold, and a depth-to-colour distance over
// 0.5 m (the file's translations are metres; a device is 10 cm wide).
K4aCalibration parse_k4a_calibration(const nlohmann::json& root, const std::string& where);

// The colour camera of the colour mode whose images are width x height (720P .. 3072P, the SDK's
// mode table), in gslift's conventions (pixels, pixel corner at 0). Legacy 16:9 calibrations are
// first mapped to 4:3 as the SDK does. Throws InputError when no colour mode has that size.
Camera k4a_colour_camera(const K4aSensor& colour, int width, int height, const std::string& where);

// The depth camera of the depth mode whose images are width x height (NFOV 2x2 binned 320 x 288,
// NFOV unbinned 640 x 576, WFOV 2x2 binned 512 x 512, WFOV unbinned 1024 x 1024); nullopt for
// any other size (a depth map registered to colour already).
std::optional<Camera> k4a_depth_camera(const K4aSensor& depth, int width, int height,
                                       const std::string& where);

// Depth-camera points to colour-camera points, metres (the SDK's extrinsics[DEPTH][COLOR]).
Pose k4a_depth_to_colour(const K4aCalibration& calibration);

}  // namespace gslift
