// RGB-D frame folders in the layouts SLAM and 3DGS code commonly ship. Both store camera-to-world
// poses in OpenCV camera axes (x right, y down, z forward).
#pragma once

#include <filesystem>
#include <vector>

#include "nodes/ingest/view_files.hpp"

namespace gslift {

// Replica as rendered by NICE-SLAM: results/frameNNNNNN.jpg and depthNNNNNN.png (16-bit, value /
// scale = metres), traj.txt with one row-major 4x4 camera-to-world per line (line i = frame i),
// and cam_params.json {"camera": {w, h, fx, fy, cx, cy, scale}} in the folder or its parent.
// Views are the frames present, named "frameNNNNNN".
std::vector<ViewFiles> read_replica_views(const std::filesystem::path& folder);

// 3DMatch / 7-Scenes: camera-intrinsics.txt (3x3 K) and seq-*/frame-NNNNNN.{color.png,
// depth.png (16-bit millimetres), pose.txt (4x4 camera-to-world)}. Views are named
// "<seq>_frame-NNNNNN"; the image size is read from the first colour image.
std::vector<ViewFiles> read_3dmatch_views(const std::filesystem::path& folder);

}  // namespace gslift
