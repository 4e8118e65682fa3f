// Multi-camera RGB-D operating-room rigs in the layout of 4D-OR and MM-OR (Özsoy et al.;
// docs/or-rig.md says exactly what is read and what is inferred): per camera a calibration
// camera0X.json, per time step one colour and one depth frame per camera. One time step is one
// capture: a folder holding colorimage/ and depthimage/, with the calibrations in it or in its
// parent (the recording, whose subfolders are its time steps).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "nodes/ingest/depth_registration.hpp"
#include "nodes/ingest/view_files.hpp"

namespace gslift {

// One camera of the rig as its camera0X.json describes it, in gslift's conventions (OpenCV axes,
// pixel corner at 0, metres).
struct OrRigCamera {
  Camera colour;
  // depth_parameters when the file has them: the depth camera's own intrinsics, depth maps are
  // then registered to colour through depth_to_colour. Without them the depth maps are taken as
  // registered to the colour camera already, at its resolution or a fraction of it.
  std::optional<Camera> depth;
  Pose colour_pose;      // world -> colour camera
  Pose depth_to_colour;  // depth-camera frame -> colour-camera frame
};

// Reads camera0X.json ({"value0": {color_parameters, depth_parameters?, camera_pose,
// color2depth_transform}}). Throws InputError naming the file and the field.
OrRigCamera read_or_rig_camera(const std::filesystem::path& file);

// A camera whose camera<N>.json is Azure Kinect's raw calibration export (k4a_calibration.hpp):
// the colour mode from the colour frames' size; the depth mode from the depth frames' size, or
// no depth camera (depth registered to colour already) when no depth mode has that size; the pose
// in the rig from camera<N>_pose.json beside it ({"value0": {"camera_pose": ...}}, as in
// camera0X.json), else the depth camera is the world. Throws InputError naming file and field.
OrRigCamera read_or_rig_k4a_camera(const std::filesystem::path& file, cv::Size colour,
                                   std::optional<cv::Size> depth);

// The camera0X.json text that read_or_rig_camera reads back as `camera`; std::invalid_argument
// for a thin-prism distortion (12 coefficients), which the format cannot hold.
std::string or_rig_camera_json(const OrRigCamera& camera);

// Whether `folder` is a rig time step: it has colorimage/, and camera<N>.json files are in it or
// in its parent.
bool is_or_rig_step(const std::filesystem::path& folder);

// The views of one time step, one per calibrated camera with a colour frame (its camera<N>.json
// either 4D-OR's calibration or Azure Kinect's raw one, told apart by the root key), named after
// the camera ("camera01"), in camera order: colorimage/<camera>_colorimage-<index>.{jpg,png} and
// depthimage/<camera>_depthimage-<index>.{tiff,tif,png} (16-bit millimetres; optional per
// view). Each view's depth map carries its DepthSensor and is registered to the colour camera
// on load. Throws InputError for a frame of an uncalibrated camera, a camera with several frames
// (several time steps in one folder), and a step without any frame; files that point outside
// `folder` are refused unless `allow_outside_paths`.
std::vector<ViewFiles> read_or_rig_views(const std::filesystem::path& folder,
                                         bool allow_outside_paths);

}  // namespace gslift
