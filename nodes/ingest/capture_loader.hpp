// Opens a capture folder of any supported layout as a Capture whose views load lazily.
#pragma once

#include <filesystem>

#include "nodes/ingest/capture_options.hpp"
#include "nodes/scene/capture.hpp"

namespace gslift {

// `path` is, in order of precedence:
//   - a folder with capture.yaml (gslift.capture/v1, docs/capture_format.md): COLMAP model,
//     images, depth prior, held-out views and ground truth as the manifest says;
//   - a COLMAP workspace: sparse/0/ or colmap/ holding cameras/images(.bin|.txt), plus images/;
//   - a COLMAP model folder itself (cameras.bin|txt inside); images/ is looked for beside it or
//     one level further up (colmap/ -> ../images, sparse/0/ -> ../../images);
//   - a NeRF folder with transforms.json (else transforms_train.json), or such a .json file;
//   - a Replica/NICE-SLAM folder (results/ + traj.txt) or a 3DMatch folder
//     (camera-intrinsics.txt + seq-*/);
//   - a time step of an OR rig recording (or_rig.hpp): colorimage/ (+ depthimage/) with
//     camera<N>.json in the folder or its parent.
// capture.yaml's `rig:` names a rig time step instead of a COLMAP model. Anything else is an
// InputError listing what was looked for. Views are in the format's order
// (COLMAP: by image name). held_out comes from capture.yaml, else options.holdout_every.
Capture load_capture(const std::filesystem::path& path, const CaptureOptions& options = {});

}  // namespace gslift
