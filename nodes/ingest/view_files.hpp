// The files of one view as a format reader finds them, and their conversion into a View with
// lazy ImageSources. Each source checks, when loaded, that its file has the size of the view's
// full-resolution camera and throws InputError naming the file otherwise; nothing is decoded
// while a capture is opened, so a capture with thousands of views opens instantly.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "nodes/ingest/capture_options.hpp"
#include "nodes/ingest/depth_registration.hpp"
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
  // Depth from a camera of its own (an RGB-D rig): the depth map has the sensor camera's size and
  // is registered to `camera` on load (depth_registration.hpp). With depth_sensor_fits_file the
  // sensor's camera is first scaled to the depth file's size (depth registered to colour at a
  // fraction of its resolution). Absent: the depth map is in `camera`, at its size.
  std::optional<DepthSensor> depth_sensor;
  bool depth_sensor_fits_file = false;
  // Ground truth, empty paths when absent.
  std::filesystem::path gt_instance, gt_semantic, gt_depth, gt_normal;
  bool held_out = false;
};

// The rectangle of the image undistorted into the same K (full resolution) that holds only pixels
// seen by the captured image, as COLMAP's image_undistorter crops: bounded by the captured image's
// border pixels undistorted, less one pixel for bilinear interpolation; width and height rounded
// down to multiples of `multiple` (the downscale). The whole image without distortion. Throws
// InputError when nothing is left.
cv::Rect undistorted_valid_rect(const Camera& camera, int multiple = 1);

// The views read at 1/options.downscale resolution: camera.scaled(1 / downscale), RGB resized
// with the area filter, depth and label maps with nearest neighbour (averaging across a depth
// edge or an instance border invents values). With options.undistort, images of a camera with
// distortion are undistorted to the same focal lengths before the resize, cropped to
// undistorted_valid_rect with options.undistort_crop (so no pixel is the black of nowhere), and
// the view's camera is that pinhole. A depth map with a depth_sensor is registered to that
// camera at full resolution before the resize.
// Views with the same camera share their undistortion maps (computed on the first load).
std::vector<View> make_views(const std::vector<ViewFiles>& files, const CaptureOptions& options);

}  // namespace gslift
