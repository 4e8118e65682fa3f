// The fuzz targets by name (fuzz/targets.cpp). Each feeds one input to one reader; success and
// gslift::InputError are the accepted outcomes, anything else escapes (a finding).
#pragma once

#include <string>
#include <vector>

namespace gslift::fuzz {

// graph_yaml, capture_yaml, colmap_text, colmap_binary, transforms_json, vlm_reply, coco_rle,
// mask_png, depth_image, ply.
const std::vector<std::string>& target_names();

// Runs target `target` on `bytes`; std::invalid_argument for an unknown target.
void run_target(const std::string& target, const std::string& bytes);

}  // namespace gslift::fuzz
