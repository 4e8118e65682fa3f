// Normals derived from a depth map: the target of the normal-consistency loss (DN-Splatter computes
// its pseudo ground-truth normals from depth the same way).
#pragma once

#include <opencv2/core.hpp>

#include "nodes/scene/camera.hpp"

namespace gslift {

// World-space unit normals (the rasterizer renders world-space normals) of a depth map (CV_32FC1
// metres, 0 = invalid) seen by camera/pose. Each pixel back-projects to P(u,v) = d K^-1 (u+0.5,
// v+0.5, 1); the normal is the normalised cross product of the central differences P(u+1,v) -
// P(u-1,v) and P(u,v+1) - P(u,v-1) in camera space, oriented to face the camera (n . P < 0), then
// rotated to the world by R^T. Pixels on the border or with an invalid neighbour get (0,0,0), which
// normal_cosine_loss treats as invalid. Also zero where the neighbours' depths differ from the
// centre by more than max_relative_jump * depth: a depth discontinuity (an occluding edge) has no
// surface normal.
cv::Mat normals_from_depth(const cv::Mat& depth, const Camera& camera, const Pose& pose,
                           double max_relative_jump = 0.1, int baseline = 1, double smoothing = 0);

// Smoothing (Gaussian sigma, pixels) of the depth prior before its normals are taken, for the
// normal loss's targets and the initial orientations. [decision] 3: on the embedded OR (depth
// noise 2%) the normals of the raw prior differ from those of the true depth by 1 - cos = 0.67 on
// average, which is why the normal loss could not fall below ~0.7; after smoothing by sigma 1.5 /
// 3 / 6 pixels by 0.16 / 0.12 / 0.17, with 95% of the pixels still given a normal.
constexpr double kPriorNormalSmoothing = 3.0;

// The depth map (CV_32FC1, 0 = invalid) smoothed by a Gaussian of sigma pixels over its valid
// pixels only (normalised convolution); invalid pixels stay 0.
cv::Mat smooth_valid_depth(const cv::Mat& depth, double sigma);

}  // namespace gslift
