// Depth-to-colour registration for RGB-D sensors whose depth camera is not the colour camera
// (Azure Kinect, the cameras of 4D-OR and MM-OR): the depth map re-expressed as the colour
// camera's z-depth on the colour camera's pixel grid, as the Azure Kinect SDK's
// k4a_transformation_depth_image_to_color_camera does (src/transformation/rgbz.c).
#pragma once

#include <opencv2/core.hpp>

#include "nodes/scene/camera.hpp"

namespace gslift {

// A depth camera of its own: its intrinsics and distortion, and where it sits relative to the
// colour camera.
struct DepthSensor {
  Camera camera;
  // Depth-camera frame -> colour-camera frame (x_colour = R x_depth + t, metres), both in
  // OpenCV axes (camera.hpp). Pose's world -> camera convention with the depth frame as world.
  Pose depth_to_colour;
};

// `depth` (CV_32FC1, metres of z in the depth camera's frame, 0 = no measurement, of the depth
// camera's size) registered to `colour` (with or without distortion): CV_32FC1 of colour's
// size holding z in the colour camera's frame, 0 where no depth lands (holes stay holes).
//
// Each depth pixel is back-projected along its ray (through the depth camera's distortion) and
// moved into the colour frame; every 2 x 2 block of valid depth pixels is two triangles projected
// into the colour image (through its distortion) and rasterised with perspective-correct
// interpolation (1/z is linear in the image for a planar triangle), so depth at a lower
// resolution than colour covers the colour pixels between its samples. Where several surfaces
// land on one colour pixel the nearest wins (a z-buffer). A triangle whose depths spread more
// than a surface seen at 86 degrees from its normal would across one depth pixel is a depth edge
// and is not drawn: the SDK skips such quads too (its bound 0.0469 z_min is about 86.4 degrees
// for its 504-pixel focal length), so edges become holes instead of smeared depth. A block with
// one invalid pixel draws the triangle of the other three.
cv::Mat register_depth(const cv::Mat& depth, const DepthSensor& sensor, const Camera& colour);

}  // namespace gslift
