// Camera in OpenCV's calls: its camera matrix, and pixels to and from rays through its
// distortion. OpenCV puts pixel centres at integer coordinates, gslift at +0.5 (camera.hpp); these
// take and return gslift coordinates.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "nodes/scene/camera.hpp"

namespace gslift {

// K with OpenCV's pixel-centre convention (cx, cy less 0.5).
cv::Mat opencv_camera_matrix(const Camera& camera);

// The normalised ideal coordinates (x/z, y/z) of the rays through `pixels`, undoing the camera's
// distortion by fixed-point iteration to convergence (OpenCV's default 5 steps leave pixels of
// error at the border of a rational or thin-prism model).
std::vector<cv::Point2d> pixel_rays(const Camera& camera, const std::vector<cv::Point2d>& pixels);

// The pixels `points` (camera frame, z > 0) project to, through the camera's distortion.
std::vector<cv::Point2d> project_to_pixels(const Camera& camera,
                                           const std::vector<cv::Point3d>& points);

}  // namespace gslift
