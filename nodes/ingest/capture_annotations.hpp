// The upstream-model outputs stored beside a capture (docs/capture_format.md): VLM grounding
// replies (vlm/<stem>/round_<k>.txt), box-prompted SAM masks (sam_box/<stem>/round_<k>.json) and
// SAM automatic masks (sam_auto/<stem>.json). Folders come from the capture's capture.yaml, or
// the defaults when it has none. All are converted to the views' pixel grid (after any
// downscale at ingest).
#pragma once

#include <string>

#include "nodes/ingest/vlm_reply.hpp"
#include "nodes/scene/boxes.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/masks.hpp"
#include "param/param_table.hpp"

namespace gslift {

struct VlmLoadOptions {
  // The VLM's coordinate space; Auto = capture.yaml's vlm.coords (norm1000 without one).
  VlmCoords coords = VlmCoords::Auto;
  // Rounds to read per view: 0 = every round_<k>.txt found (k = 0, 1, ... until one is absent);
  // n > 0 = exactly rounds 0..n-1, a missing file being an InputError.
  int rounds = 0;
};

// The params of ingest.vlm: one entry per field above.
const ParamTable<VlmLoadOptions>& vlm_load_param_table();

// One ViewBoxes per capture view, in view order; a view without replies has no boxes. Replies
// that do not parse are skipped as parse_view_replies (vlm_reply.hpp) says; their count goes to
// `rounds_unparsed` when given.
BoxSet load_vlm_boxes(const Capture& capture, const VlmLoadOptions& options = {},
                      int* rounds_unparsed = nullptr);

// Box-prompted SAM masks for `boxes` (from load_vlm_boxes, or clusters of them): the mask at
// position j of round_<k>.json belongs to the box with round k and source_index j; Mask::box_index
// is that box's index in its ViewBoxes and Mask::label its label. Masks whose box was dropped
// (degenerate) and null entries are left out. A capture built in memory (no root folder) has none.
MaskSet load_sam_box_masks(const Capture& capture, const BoxSet& boxes);

// SAM automatic masks of every view that has a sam_auto/<stem>.json, in view order.
MaskSet load_sam_auto_masks(const Capture& capture);

}  // namespace gslift
