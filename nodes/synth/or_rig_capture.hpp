// Writes the embedded OR as a recording of a multi-camera RGB-D rig in 4D-OR / MM-OR's layout
// (nodes/ingest/or_rig.hpp, docs/or-rig.md), so that the rig reader is tested end to end
// against exact ground truth: each camera's colour image through OpenCV's rational distortion,
// its depth from a depth camera of its own resolution, distortion and viewpoint.
#pragma once

#include <filesystem>
#include <string>

#include "nodes/ingest/or_rig.hpp"
#include "nodes/synth/or_capture.hpp"

namespace gslift::synth {

// The rig camera around one of the scene's pinhole cameras (its pose world -> colour): colour
// with the same intrinsics under a barrel-type rational distortion (k1..k6, p1, p2); depth at
// half the colour's focal length on a 320 x 288 sensor per 640 x 480 of colour (Azure Kinect's
// NFOV depth has about half the colour camera's focal length) with a Brown-Conrady distortion,
// 3.2 cm beside the colour camera and turned by 1.5 degrees, as an Azure Kinect's depth camera
// sits beside and tilted from its colour camera.
OrRigCamera rig_camera(const Camera& pinhole, const Pose& colour_pose);

// Where a rig writes its depth frames: from the depth camera of rig_camera (4D-OR's raw frames),
// or registered to the colour camera already, in its captured (distorted) grid at half its
// resolution and without depth_parameters in the calibration (MM-OR's depthimage/, whose public
// fusion code upsamples depth by 2 and back-projects it with the colour intrinsics).
enum class RigDepth { sensor, registered };

// "camera01", ... for camera index 0, ...; "000000", ... for time step 0, ....
std::string rig_camera_name(int index);
std::string rig_step_name(int step);

// Writes out_dir/camera<NN>.json per camera and out_dir/<step>/ per time step, each a capture:
// colorimage/<camera>_colorimage-<step>.png, depthimage/<camera>_depthimage-<step>.tiff (16-bit
// millimetres, with the depth prior's noise and holes of the knobs), and, as gslift's own layout
// has them, ground truth in the colour images' grid, simulated VLM replies and SAM masks in the
// grid of the images as the reader loads them (undistorted, cropped to the valid region), and a
// capture.yaml with `rig: .`. The scene is static: every time step holds the same frames. The
// written colour poses carry the knobs' pose noise, as gslift's layout does. Atomic as
// write_or_capture; time_steps from 1 to 1000 (std::invalid_argument otherwise).
void write_or_rig_recording(const OrCaptureSettings& settings, const std::filesystem::path& out_dir,
                            int time_steps, RigDepth depth = RigDepth::sensor);

}  // namespace gslift::synth
