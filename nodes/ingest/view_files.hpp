// The files of one view as a format reader finds them, and their conversion into a View with
// lazy ImageSources. Each source checks, when loaded, that its file has the size of the view's
// full-resolution camera and throws InputError naming the file otherwise; nothing is decoded
// while a capture is opened, so a capture with thousands of views opens instantly.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "nodes/scene/camera.hpp"
#include "nodes/scene/capture.hpp"

namespace gslift {

struct ViewFiles {
  std::string name;  // the image name without extension
  Camera camera;     // full resolution
  Pose pose;         // world -> camera
  std::filesystem::path rgb;
  std::filesystem::path depth;  // empty = no depth prior
  double depth_scale = 1000;    // 16-bit depth value / depth_scale = metres
  // Ground truth, empty paths when absent.
  std::filesystem::path gt_instance, gt_semantic, gt_depth, gt_normal;
  bool held_out = false;
};

// The view read at 1/downscale resolution: camera.scaled(1 / downscale), RGB resized with the
// area filter, depth and label maps with nearest neighbour (averaging across a depth edge or an
// instance border invents values). With `undistort`, images of a camera with distortion are
// undistorted to the same K before the resize and the view's camera has no distortion.
View make_view(const ViewFiles& files, int downscale, bool undistort);

}  // namespace gslift
