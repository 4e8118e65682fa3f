// The failure-mode knobs of the simulated upstream models (VLM, SAM, MVS depth, poses) and of the
// renderer. Defaults are the "default" preset; `easy` and `hard` move every failure rate in the
// same direction. Every knob is settable by name (`gslift synth --set vlm_miss_rate=0.3`, the
// synth.capture node's params), and its ParamTable (synth_knob_table) is the single source for
// parsing, ranges, the node's ParamSpecs, `gslift synth --help` and docs/synth.md's knob table.
#pragma once

#include <string>
#include <vector>

#include "param/param_table.hpp"

namespace gslift::synth {

struct SynthKnobs {
  // VLM (Qwen-VL grounding), LangOR's robust perceptor asks N rounds per image.
  int vlm_rounds = 5;                // rounds of answers per view
  double vlm_miss_rate = 0.15;       // P(a visible instance gets no box in a round)
  double vlm_jitter = 0.05;          // sigma of each box edge, as a fraction of box width/height
  double vlm_confusion_rate = 0.15;  // P(a person's label is swapped for another look-alike role)
  double vlm_hallucination_rate = 0.3;  // expected boxes per view and round covering nothing real
  double vlm_min_visible = 0.002;       // an instance is "visible" above this fraction of the image
  // SAM prompted with boxes.
  double sam_boundary_noise = 1.5;  // amplitude (pixels) of the smooth boundary displacement
  double sam_leak_rate = 0.1;       // P(a mask also takes a neighbouring instance inside the box)
  // SAM automatic mask generator (per view, inconsistent across views).
  double sam_auto_split_rate = 0.25;  // P(an instance comes out as its parts: head/torso/legs...)
  double sam_auto_merge_rate = 0.1;   // P(an instance is merged with its most adjacent neighbour)
  double sam_auto_fragments = 2.0;    // expected small spurious fragments per view
  int sam_auto_granularities = 2;     // 1: whole-object masks only; 2: also part masks (SAGA)
  // Feed-forward MVS depth prior (VGGT-like) and poses.
  double depth_noise = 0.02;  // relative sigma of the depth prior (half smooth, half per pixel)
  double depth_holes = 0.03;  // fraction of depth-prior pixels set invalid (0), in blobs
  double pose_noise_deg = 0;  // sigma of the rotation error of the written poses (degrees)
  double pose_noise_m = 0;    // sigma of the camera-centre error of the written poses (metres)
  // Scene.
  double drapes = 0;  // fraction of the equipment under textureless drapes (nodes/synth/drapes.hpp)
  // Rendering and initialisation.
  bool shadows = true;        // hard shadows from every light
  int sparse_points = 20000;  // SfM/MVS-like coloured points sampled from the training views
  // Units: the written capture's lengths (poses, depth, points) are the room's metres times this,
  // as a capture in centimetres (100) or of a model-sized room (0.01) has them. The images are
  // the same; what reads the capture must not depend on its units (issue 29's scale test).
  double world_scale = 1;
};

// The failure rates of the simulated models, as a whole.
enum class SynthPreset { Easy, Default, Hard };
const EnumNames<SynthPreset>& preset_names();  // easy, default, hard
SynthKnobs preset_knobs(SynthPreset preset);

// Every knob, in declaration order: name, field, range, doc.
using KnobField = ParamTable<SynthKnobs>::Field;
const ParamTable<SynthKnobs>& synth_knob_table();

// Sets knob `name` from its text value ("0.3", "true", "5"); throws std::invalid_argument naming
// the knob and what is wrong (unknown name, not a number, out of range).
void set_knob(SynthKnobs& knobs, const std::string& name, const std::string& value);
// The knob's value as text, locale-independent and exact (round-trips through set_knob).
std::string knob_value(const SynthKnobs& knobs, const KnobField& knob);

}  // namespace gslift::synth
