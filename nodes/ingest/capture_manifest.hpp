// capture.yaml, the manifest of a gslift.capture/v1 folder (docs/capture_format.md). Captures
// without one (plain COLMAP workspaces, transforms.json folders) get the defaults below, so the
// annotation folders (vlm/, sam_box/, sam_auto/) are found the same way in both.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "nodes/ingest/vlm_reply.hpp"

namespace gslift {

struct CaptureManifest {
  std::string name;                          // empty = the folder name
  std::filesystem::path model = "sparse/0";  // COLMAP model folder, relative to the root
  std::filesystem::path rig;  // instead of model: an OR rig time step (or_rig.hpp); empty = none
  std::filesystem::path images = "images";     // folder the model's image names are relative to
  std::filesystem::path depth;                 // depth prior folder; empty = none
  double depth_scale = 1000;                   // 16-bit depth value / depth_scale = metres
  bool has_held_out = false;                   // whether held_out was given (it may be empty)
  std::vector<std::string> held_out;           // test view names
  std::filesystem::path vlm = "vlm";           // vlm/<stem>/round_<k>.txt
  int vlm_rounds = 0;                          // rounds asked; 0 = unknown (count the files)
  VlmCoords vlm_coords = VlmCoords::Norm1000;  // never Auto
  int vlm_input_width = 0;                     // the VLM's resized input, for resized_abs
  int vlm_input_height = 0;
  std::filesystem::path sam_box = "sam_box";    // sam_box/<stem>/round_<k>.json
  std::filesystem::path sam_auto = "sam_auto";  // sam_auto/<stem>.json
  std::filesystem::path gt;                     // ground-truth folder; empty = none
};

// Reads <root>/capture.yaml when it exists, else returns the defaults. Throws InputError naming
// the file for a wrong `format`, mistyped fields, an unknown vlm.coords, a capture.yaml that is
// not a regular file, and (unless `allow_outside_paths`) a folder that points outside `root`.
CaptureManifest read_capture_manifest(const std::filesystem::path& root,
                                      bool allow_outside_paths = false);

}  // namespace gslift
