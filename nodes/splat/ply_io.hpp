// The INRIA 3DGS PLY layout, so a model written here opens in common 3DGS viewers and a PLY from
// the reference 3DGS code loads here.
//
// One `vertex` element, binary little endian, float properties in this exact order:
//   x y z nx ny nz f_dc_0 f_dc_1 f_dc_2 f_rest_0 .. f_rest_{3(K-1)-1} opacity
//   scale_0 scale_1 scale_2 rot_0 rot_1 rot_2 rot_3
// then the extras of this project: feat_0 .. feat_{D-1} (float) and instance_id, class_id (int),
// each only when the model has them. Values are pre-activation (log-scales, opacity logits,
// unnormalised w-first quaternions); nx ny nz are written as 0 as INRIA does. f_rest is
// channel-major: f_rest_{c (K-1) + k - 1} = SH coefficient k of channel c. INRIA's loader collects
// properties by prefix ("f_rest_", "scale_", "rot"), so extras never start with those prefixes.
#pragma once

#include <filesystem>

#include "nodes/scene/gaussian_model.hpp"

namespace gslift {

// Writes atomically (base/atomic_file.hpp).
void write_ply(const GaussianModel& model, const std::filesystem::path& path);

// Reads binary little-endian or ASCII PLY files with the INRIA properties in any order and any
// scalar type; other properties and other elements (after the vertices) are ignored. The SH degree
// follows from the number of f_rest_* properties, the feature dimension from feat_*. Throws
// InputError naming the file for anything missing, truncated or inconsistent.
GaussianModel read_ply(const std::filesystem::path& path);

}  // namespace gslift
