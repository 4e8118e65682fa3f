// A simulated grounding VLM (Qwen3-VL style): for each round, a box + label for each visible
// instance unless missed, with jitter, look-alike label confusions and hallucinated boxes. The
// reply is the raw text the model would return: a ```json fenced list of
// {"bbox_2d": [x1, y1, x2, y2], "label": ...} with coordinates normalised to 0..1000.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "nodes/scene/boxes.hpp"
#include "nodes/synth/synth_knobs.hpp"
#include "nodes/synth/visible_instances.hpp"

namespace gslift::synth {

struct VlmBox {
  Box box;                  // XYXY pixels as ingest will decode them (after norm1000 rounding)
  int source_instance = 0;  // the instance it was drawn from, 0 = hallucinated
  int true_class = 0;       // that instance's class (0 when hallucinated)
  int label_class = 0;      // the class whose name is the label
};

struct VlmRound {
  std::vector<VlmBox> boxes;  // in reply order
  std::string reply;          // raw model output
};

// Rounds for one view of size width x height; deterministic in `seed`.
std::vector<VlmRound> simulate_vlm(const std::vector<VisibleInstance>& visible, int width,
                                   int height, const SynthKnobs& knobs, uint64_t seed);

// The context-aware prompt (LangOR 1.1): each class with where it is, what it does and what it
// looks like, and the answer format.
std::string vlm_prompt();

}  // namespace gslift::synth
