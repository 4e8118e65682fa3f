#include "nodes/synth/synth_knobs.hpp"

#include <cstdlib>
#include <locale>
#include <sstream>
#include <stdexcept>

#include "base/utf8.hpp"

namespace gslift::synth {

const EnumNames<SynthPreset>& preset_names() {
  static const EnumNames<SynthPreset> names = {
      {SynthPreset::Easy, "easy"}, {SynthPreset::Default, "default"}, {SynthPreset::Hard, "hard"}};
  return names;
}

SynthKnobs preset_knobs(SynthPreset preset) {
  SynthKnobs k;
  if (preset == SynthPreset::Default) return k;
  if (preset == SynthPreset::Easy) {
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
  // Hard.
  {
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
}

const ParamTable<SynthKnobs>& synth_knob_table() {
  using K = SynthKnobs;
  static const ParamTable<K> table =
      ParamTable<K>()
          .add("vlm_rounds", &K::vlm_rounds, "rounds of VLM answers per view (LangOR: 5)", 1, 20)
          .add("vlm_miss_rate", &K::vlm_miss_rate,
               "probability that a visible instance gets no box in a round", 0, 1)
          .add("vlm_jitter", &K::vlm_jitter,
               "sigma of each box edge as a fraction of the box width/height", 0, 1)
          .add("vlm_confusion_rate", &K::vlm_confusion_rate,
               "probability that a person's label is swapped for another look-alike role", 0, 1)
          .add("vlm_hallucination_rate", &K::vlm_hallucination_rate,
               "expected hallucinated boxes (covering nothing real) per view and round", 0, 20)
          .add("vlm_min_visible", &K::vlm_min_visible,
               "fraction of the image an instance must cover to be reported", 0, 1)
          .add("sam_boundary_noise", &K::sam_boundary_noise,
               "amplitude in pixels of the smooth displacement of SAM mask boundaries", 0, 50)
          .add("sam_leak_rate", &K::sam_leak_rate,
               "probability that a box-prompted mask leaks into a neighbouring instance", 0, 1)
          .add("sam_auto_split_rate", &K::sam_auto_split_rate,
               "probability that an automatic mask splits an instance into its parts", 0, 1)
          .add("sam_auto_merge_rate", &K::sam_auto_merge_rate,
               "probability that an automatic mask merges an instance with its neighbour", 0, 1)
          .add("sam_auto_fragments", &K::sam_auto_fragments,
               "expected small spurious automatic-mask fragments per view", 0, 100)
          .add("sam_auto_granularities", &K::sam_auto_granularities,
               "automatic-mask levels: 1 whole objects, 2 also parts (SAGA)", 1, 2)
          .add("depth_noise", &K::depth_noise, "relative sigma of the depth prior", 0, 1)
          .add("depth_holes", &K::depth_holes, "fraction of depth-prior pixels that are invalid", 0,
               0.9)
          .add("pose_noise_deg", &K::pose_noise_deg,
               "sigma of the rotation error of the written poses, degrees", 0, 30)
          .add("pose_noise_m", &K::pose_noise_m,
               "sigma of the camera-centre error of the written poses, metres", 0, 1)
          .add("drapes", &K::drapes,
               "fraction of the equipment covered by textureless sterile drapes (no SfM points "
               "there)",
               0, 1)
          .add("shadows", &K::shadows, "render hard shadows from every light")
          .add("sparse_points", &K::sparse_points,
               "coloured sparse points sampled from the training views (SfM/MVS initialisation)", 0,
               1000000)
          .add("world_scale", &K::world_scale,
               "lengths written (poses, depth, points) = the room's metres x this (the capture's "
               "units; images unchanged)",
               1e-3, 1e3);
  return table;
}

namespace {

const KnobField& find_knob(const std::string& name) {
  for (const KnobField& k : synth_knob_table().fields()) {
    if (k.spec.name == name) return k;
  }
  std::string known;
  for (const KnobField& k : synth_knob_table().fields())
    known += (known.empty() ? "" : ", ") + k.spec.name;
  throw std::invalid_argument("unknown synth knob '" + name + "' (known: " + known + ")");
}

double parse_number(const ParamSpec& info, const std::string& text) {
  std::istringstream in(text);
  in.imbue(std::locale::classic());
  double v = 0;
  in >> v;
  if (text.empty() || in.fail() || !(in >> std::ws).eof()) {
    throw std::invalid_argument("synth knob " + info.name + ": '" + printable(text) +
                                "' is not a number");
  }
  if (v < *info.min || v > *info.max) {
    std::ostringstream msg;
    msg.imbue(std::locale::classic());
    msg << "synth knob " << info.name << " = " << text << " is outside [" << *info.min << ", "
        << *info.max << "]";
    throw std::invalid_argument(msg.str());
  }
  return v;
}

}  // namespace

void set_knob(SynthKnobs& knobs, const std::string& name, const std::string& value) {
  const KnobField& knob = find_knob(name);
  switch (knob.spec.type) {
    case ParamType::Bool:
      if (value == "true" || value == "1") {
        knob.set(knobs, true);
      } else if (value == "false" || value == "0") {
        knob.set(knobs, false);
      } else {
        throw std::invalid_argument("synth knob " + name + ": '" + value + "' is not a bool");
      }
      return;
    case ParamType::Int: {
      const double v = parse_number(knob.spec, value);
      if (v != static_cast<int>(v)) {
        throw std::invalid_argument("synth knob " + name + ": '" + value + "' is not an integer");
      }
      knob.set(knobs, static_cast<int64_t>(v));
      return;
    }
    default:
      knob.set(knobs, parse_number(knob.spec, value));
  }
}

std::string knob_value(const SynthKnobs& knobs, const KnobField& knob) {
  const ParamValue value = knob.get(knobs);
  if (const bool* b = std::get_if<bool>(&value)) return *b ? "true" : "false";
  if (const int64_t* i = std::get_if<int64_t>(&value)) return std::to_string(*i);
  // The shortest decimal that reads back as the same double ("0.15", not 0.14999999999999999).
  const double v = std::get<double>(value);
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
