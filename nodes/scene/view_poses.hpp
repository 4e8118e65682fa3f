// A pose per view of a capture, by view name: the poses splat.reconstruct refined against the
// photos (nodes/splat/pose_correction.hpp), which splat.refined_capture puts into the capture the
// later stages render with, and which `gslift view` and `gslift segment` read back from a run's
// refined_poses.txt so that a click lands where the model was trained to see it.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "base/port_type.hpp"
#include "nodes/scene/camera.hpp"

namespace gslift {

struct Capture;

struct ViewPoses {
  std::vector<std::string> views;  // view names, the capture's order
  std::vector<Pose> poses;         // world -> camera, one per name
};

GSLIFT_PORT_TYPE(ViewPoses, "ViewPoses");

// refined_poses.txt: a comment line, then a line per view "name qw qx qy qz tx ty tz" (world ->
// camera, as COLMAP's images.txt), 17 significant digits: read back to double precision.
std::string view_poses_text(const ViewPoses& poses);
// Parses that text; `source` (the file) names a malformed line in the InputError it throws.
ViewPoses parse_view_poses(const std::string& text, const std::string& source);
// The file's text parsed; a directory, a FIFO or a missing file is an InputError naming it
// (base/input_file.hpp: the path comes from a user).
ViewPoses read_view_poses(const std::filesystem::path& file);

// Puts the poses into the capture, view by view. Throws InputError naming `source` where their
// count or a name differs from the capture's views (poses of another capture).
void apply_view_poses(Capture& capture, const ViewPoses& poses, const std::string& source);

}  // namespace gslift
