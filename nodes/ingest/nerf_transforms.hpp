// NeRF / instant-ngp / nerfstudio `transforms.json` captures.
//
// Intrinsics come from fl_x/fl_y/cx/cy/w/h, or from camera_angle_x (and camera_angle_y) as in
// the Blender scenes (fx = w / 2 / tan(camera_angle_x / 2)); every key may be overridden per
// frame. Missing w/h are taken from the first image; missing cx/cy default to the image centre.
// OpenCV distortion k1 k2 p1 p2 [k3] is kept in Camera::distortion; a nerfstudio camera_model
// other than OPENCV, PINHOLE or SIMPLE_PINHOLE (fisheye, equirectangular) is rejected.
// `transform_matrix` is camera-to-world in OpenGL camera axes (x right, y up, looking down -z) and
// is converted to the OpenCV world-to-camera pose gslift uses. `file_path` may omit the extension
// (.png, .jpg and .jpeg are tried). nerfstudio's `depth_file_path` becomes the depth prior, 16-bit
// millimetres (nerfstudio's default depth_unit_scale_factor 1e-3).
//
// Frames whose image is absent are skipped with one warning (instant-ngp does the same; the fox
// and lego scenes here list more frames than they ship). RGBA images (the Blender scenes) are
// composited onto white, the background they were rendered for; read_alpha gives the mask.
#pragma once

#include <filesystem>
#include <vector>

#include "nodes/ingest/view_files.hpp"

namespace gslift {

// Frame file names (file_path, depth_file_path) must stay inside the file's folder unless
// `allow_outside_paths` (the ingest param).
std::vector<ViewFiles> read_nerf_transforms(const std::filesystem::path& json_file,
                                            bool allow_outside_paths = false);

// The OpenCV world-to-camera pose of an OpenGL/NeRF camera-to-world matrix.
Pose pose_from_opengl_c2w(const Eigen::Matrix4d& c2w);

}  // namespace gslift
