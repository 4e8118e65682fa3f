#include "nodes/synth/synth_knobs.hpp"

#include <cstdlib>
#include <locale>
#include <sstream>
#include <stdexcept>

namespace gslift::synth {

const std::vector<std::string>& preset_names() {
  static const std::vector<std::string> names = {"easy", "default", "hard"};
  return names;
}

SynthKnobs preset_knobs(const std::string& preset) {
  SynthKnobs k;
  if (preset == "default") return k;
  if (preset == "easy") {
    k.vlm_miss_rate = 0.05;
    k.vlm_jitter = 0.02;
    k.vlm_confusion_rate = 0.05;
    k.vlm_hallucination_rate = 0.05;
    k.sam_boundary_noise = 0.5;
    k.sam_leak_rate = 0.02;
    k.sam_auto_split_rate = 0.1;
    k.sam_auto_merge_rate = 0.03;
    k.sam_auto_fragments = 0.5;
    k.depth_noise = 0.005;
    k.depth_holes = 0.01;
    return k;
  }
  if (preset == "hard") {
    k.vlm_miss_rate = 0.3;
    k.vlm_jitter = 0.1;
    k.vlm_confusion_rate = 0.35;
    k.vlm_hallucination_rate = 0.8;
    k.sam_boundary_noise = 3.0;
    k.sam_leak_rate = 0.25;
    k.sam_auto_split_rate = 0.4;
    k.sam_auto_merge_rate = 0.2;
    k.sam_auto_fragments = 6.0;
    k.depth_noise = 0.05;
    k.depth_holes = 0.08;
    k.pose_noise_deg = 0.5;
    k.pose_noise_m = 0.02;
    return k;
  }
  throw std::invalid_argument("unknown preset '" + preset + "' (expected easy, default or hard)");
}

const std::vector<KnobInfo>& synth_knob_table() {
  using K = SynthKnobs;
  static const std::vector<KnobInfo> table = {
      {"vlm_rounds", &K::vlm_rounds, 1, 20, "rounds of VLM answers per view (LangOR: 5)"},
      {"vlm_miss_rate", &K::vlm_miss_rate, 0, 1,
       "probability that a visible instance gets no box in a round"},
      {"vlm_jitter", &K::vlm_jitter, 0, 1,
       "sigma of each box edge as a fraction of the box width/height"},
      {"vlm_confusion_rate", &K::vlm_confusion_rate, 0, 1,
       "probability that a person's label is swapped for another look-alike role"},
      {"vlm_hallucination_rate", &K::vlm_hallucination_rate, 0, 20,
       "expected hallucinated boxes (covering nothing real) per view and round"},
      {"vlm_min_visible", &K::vlm_min_visible, 0, 1,
       "fraction of the image an instance must cover to be reported"},
      {"sam_boundary_noise", &K::sam_boundary_noise, 0, 50,
       "amplitude in pixels of the smooth displacement of SAM mask boundaries"},
      {"sam_leak_rate", &K::sam_leak_rate, 0, 1,
       "probability that a box-prompted mask leaks into a neighbouring instance"},
      {"sam_auto_split_rate", &K::sam_auto_split_rate, 0, 1,
       "probability that an automatic mask splits an instance into its parts"},
      {"sam_auto_merge_rate", &K::sam_auto_merge_rate, 0, 1,
       "probability that an automatic mask merges an instance with its neighbour"},
      {"sam_auto_fragments", &K::sam_auto_fragments, 0, 100,
       "expected small spurious automatic-mask fragments per view"},
      {"sam_auto_granularities", &K::sam_auto_granularities, 1, 2,
       "automatic-mask levels: 1 whole objects, 2 also parts (SAGA)"},
      {"depth_noise", &K::depth_noise, 0, 1, "relative sigma of the depth prior"},
      {"depth_holes", &K::depth_holes, 0, 0.9, "fraction of depth-prior pixels that are invalid"},
      {"pose_noise_deg", &K::pose_noise_deg, 0, 30,
       "sigma of the rotation error of the written poses, degrees"},
      {"pose_noise_m", &K::pose_noise_m, 0, 1,
       "sigma of the camera-centre error of the written poses, metres"},
      {"shadows", &K::shadows, 0, 1, "render hard shadows from every light"},
      {"sparse_points", &K::sparse_points, 0, 1000000,
       "coloured sparse points sampled from the training views (SfM/MVS initialisation)"},
  };
  return table;
}

namespace {

const KnobInfo& find_knob(const std::string& name) {
  for (const KnobInfo& k : synth_knob_table()) {
    if (k.name == name) return k;
  }
  std::string known;
  for (const KnobInfo& k : synth_knob_table()) known += (known.empty() ? "" : ", ") + k.name;
  throw std::invalid_argument("unknown synth knob '" + name + "' (known: " + known + ")");
}

double parse_number(const KnobInfo& info, const std::string& text) {
  std::istringstream in(text);
  in.imbue(std::locale::classic());
  double v = 0;
  in >> v;
  if (text.empty() || in.fail() || !(in >> std::ws).eof()) {
    throw std::invalid_argument("synth knob " + info.name + ": '" + text + "' is not a number");
  }
  if (v < info.min || v > info.max) {
    std::ostringstream msg;
    msg.imbue(std::locale::classic());
    msg << "synth knob " << info.name << " = " << text << " is outside [" << info.min << ", "
        << info.max << "]";
    throw std::invalid_argument(msg.str());
  }
  return v;
}

}  // namespace

void set_knob(SynthKnobs& knobs, const std::string& name, const std::string& value) {
  const KnobInfo& info = find_knob(name);
  if (auto f = std::get_if<bool SynthKnobs::*>(&info.field)) {
    if (value == "true" || value == "1") {
      knobs.*(*f) = true;
    } else if (value == "false" || value == "0") {
      knobs.*(*f) = false;
    } else {
      throw std::invalid_argument("synth knob " + name + ": '" + value + "' is not a bool");
    }
  } else if (auto f = std::get_if<int SynthKnobs::*>(&info.field)) {
    const double v = parse_number(info, value);
    if (v != static_cast<int>(v)) {
      throw std::invalid_argument("synth knob " + name + ": '" + value + "' is not an integer");
    }
    knobs.*(*f) = static_cast<int>(v);
  } else {
    knobs.*std::get<double SynthKnobs::*>(info.field) = parse_number(info, value);
  }
}

std::string knob_value(const SynthKnobs& knobs, const KnobInfo& info) {
  if (auto f = std::get_if<bool SynthKnobs::*>(&info.field)) return knobs.*(*f) ? "true" : "false";
  if (auto f = std::get_if<int SynthKnobs::*>(&info.field)) return std::to_string(knobs.*(*f));
  // The shortest decimal that reads back as the same double ("0.15", not 0.14999999999999999).
  const double v = knobs.*std::get<double SynthKnobs::*>(info.field);
  std::string text;
  for (int precision = 6; precision <= 17; ++precision) {
    std::ostringstream out;
    out.imbue(std::locale::classic());
    out.precision(precision);
    out << v;
    text = out.str();
    std::istringstream in(text);
    in.imbue(std::locale::classic());
    double back = 0;
    in >> back;
    if (back == v) break;
  }
  return text;
}

}  // namespace gslift::synth
