// Parsing of VLM grounding replies (Qwen-VL style) into XYXY pixel boxes.
//
// A reply is free text holding one JSON array of {"bbox_2d": [x1, y1, x2, y2], "label": "..."}
// (also accepted: the key "bbox", an optional numeric "score", and a single object instead of
// an array), possibly fenced in ```json ... ``` and surrounded by prose. The first JSON value
// (inside the first fence when there is one) is taken.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "nodes/scene/boxes.hpp"
#include "param/param_table.hpp"

namespace gslift {

// The coordinate space the VLM answers in.
enum class VlmCoords {
  Norm1000,    // 0..1000 relative to the image (Qwen2-VL, Qwen3-VL): x * W / 1000
  ResizedAbs,  // absolute pixels of the model's resized input (Qwen2.5-VL): x * W / input_w
  Pixels,      // pixels of the original image: x * pixel_scale
  // Not a space: "as the capture's capture.yaml says" (ingest.vlm's default); the parser rejects
  // it, a reader replaces it first.
  Auto,
};

// The names of the three spaces: norm1000, resized_abs, pixels (Auto left out).
const EnumNames<VlmCoords>& vlm_coords_names();

struct VlmFrame {
  VlmCoords coords = VlmCoords::Norm1000;
  int input_width = 0, input_height = 0;  // ResizedAbs only: the model's input size
  // The image the boxes are for (after any downscale at ingest); boxes are clamped to it.
  int image_width = 0, image_height = 0;
  // Pixels only: image_width / the width of the image the VLM saw (1 without downscale).
  double pixel_scale = 1;
};

// Boxes of one reply in image pixels, clamped to the image, in reply order. Box::round = round,
// Box::source_index = position in the reply. Degenerate boxes (empty after clamping) are
// dropped with a warning, so source_index may skip values. Malformed replies (no JSON value,
// unterminated or invalid JSON, a bbox that is not 4 numbers) throw InputError starting with
// `source` (the file name).
std::vector<Box> parse_vlm_reply(const std::string& text, const VlmFrame& frame, int round,
                                 const std::string& source);

// The boxes of one view's grounding replies, replies[k] being round k's (the one loop behind
// ingest.vlm and vlm.query, so that a capture vlm.query writes reads back the same).
// [decision] A reply the parser rejects costs its round only: it is skipped with a warning and
// counted in `unparsed`, because a VLM answering nonsense once is what multi-round clustering is
// there for. A view with replies none of which parses has nothing left to cluster: InputError.
// ViewBoxes::rounds = replies.size(); `source(k)` names round k's reply in messages.
struct ViewReplies {
  ViewBoxes boxes;
  int unparsed = 0;  // rounds skipped
};
ViewReplies parse_view_replies(const std::string& view, const std::vector<std::string>& replies,
                               const VlmFrame& frame,
                               const std::function<std::string(int round)>& source);

}  // namespace gslift
