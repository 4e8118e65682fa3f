// A 3-view gslift.capture/v1 folder (8 x 6 images, views cam_00..cam_02, depth prior, ground
// truth), written with the same writers the synthetic generator uses.
#pragma once

#include <filesystem>
#include <string>

namespace gslift::test {

// Written into a fresh scratch folder `name`; `manifest_extra` is appended to capture.yaml.
std::filesystem::path write_small_capture(const std::string& name,
                                          const std::string& manifest_extra);

}  // namespace gslift::test
