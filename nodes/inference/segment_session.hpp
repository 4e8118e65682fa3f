// `gslift segment MODEL.ply --input CAPTURE`: an interactive SAGA session. The feature model and
// the capture are loaded once; then every stdin line is one prompt as JSON (prompt_io.hpp) plus
// optional fields
//   "output": "<dir>"          write <view>__<name>_mask.png / _overlay.png there, and with
//   "ply": true                also <name>.ply (the object alone) and scene_selection.ply
//   "views": ["cam_01", ...]   views to render the mask in ("all" = every view; default: the
//                              prompt's own view)
//   "filter": true             3D post-processing (inference.filter_3d) before rendering
// and every prompt gets one JSON line on stdout:
//   {"ok": true, "name": ..., "selected": <Gaussians>, "views": [...], "select_ms": ...,
//    "mask_ms": ..., "latency_ms": ...}
// or {"ok": false, "line": <n>, "error": "..."} for a bad prompt (unknown view, pixel outside the
// view, empty mask, malformed JSON); the session goes on. Scriptable by a GUI or a notebook.
#pragma once

#include <iosfwd>

#include "nodes/inference/prompt_segmentation.hpp"

namespace gslift {

// Answers the prompts of `in` (one JSON object per line; blank lines are skipped) until its end.
// Returns the number of prompts answered without error.
int run_segment_session(const GaussianModel& model, const Capture& capture,
                        const PromptOptions& options, std::istream& in, std::ostream& out);

// The command: argv[0] is "segment". Returns a process exit code (runtime/exit_codes.hpp).
int segment_main(int argc, char** argv);

}  // namespace gslift
