#include "nodes/synth/vlm_simulator.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "nodes/synth/or_scene.hpp"
#include "nodes/synth/stream_purpose.hpp"

namespace gslift::synth {

namespace {

// Qwen3-VL's coordinate space: integers 0..1000 across the image.
int to_norm1000(double pixel, int size) {
  return std::clamp(static_cast<int>(std::lround(pixel / size * 1000.0)), 0, 1000);
}
float from_norm1000(int v, int size) {
  return static_cast<float>(v * size / 1000.0);
}

// A confusable role other than `class_id`, uniformly.
int confused_class(int class_id, RandomStream& rng) {
  std::vector<int> others;
  for (int c = 1; c <= kOrClassCount; ++c) {
    if (c != class_id && is_look_alike_class(c)) others.push_back(c);
  }
  return others[rng.below(static_cast<int>(others.size()))];
}

// Adds the box to the round with its norm1000 quantisation; degenerate boxes are dropped (the
// model would not return a zero-area box).
void emit(VlmRound& round, std::ostringstream& json, double x1, double y1, double x2, double y2,
          int width, int height, VlmBox b) {
  if (x1 > x2) std::swap(x1, x2);
  if (y1 > y2) std::swap(y1, y2);
  const int q[4] = {to_norm1000(x1, width), to_norm1000(y1, height), to_norm1000(x2, width),
                    to_norm1000(y2, height)};
  if (q[2] <= q[0] || q[3] <= q[1]) return;
  b.box.x1 = from_norm1000(q[0], width), b.box.y1 = from_norm1000(q[1], height);
  b.box.x2 = from_norm1000(q[2], width), b.box.y2 = from_norm1000(q[3], height);
  b.box.label = or_class_names().at(b.label_class);
  json << (round.boxes.empty() ? "\n" : ",\n") << "\t{\"bbox_2d\": [" << q[0] << ", " << q[1]
       << ", " << q[2] << ", " << q[3] << "], \"label\": \"" << b.box.label << "\"}";
  round.boxes.push_back(b);
}

}  // namespace

std::vector<VlmRound> simulate_vlm(const std::vector<VisibleInstance>& visible, int width,
                                   int height, const SynthKnobs& knobs, uint64_t seed) {
  std::vector<VlmRound> rounds(knobs.vlm_rounds);
  for (int r = 0; r < knobs.vlm_rounds; ++r) {
    RandomStream rng(stream_seed(seed, kVlmStream, r));
    // Answer order varies between rounds, as a sampled model's does.
    std::vector<int> order(visible.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
    rng.shuffle(order.begin(), order.end());

    VlmRound& round = rounds[r];
    std::ostringstream json;
    json.imbue(std::locale::classic());
    for (int i : order) {
      const VisibleInstance& v = visible[i];
      if (rng.chance(knobs.vlm_miss_rate)) continue;
      const double bw = v.box.width(), bh = v.box.height();
      const double s = knobs.vlm_jitter;
      VlmBox b;
      b.source_instance = v.instance;
      b.true_class = v.class_id;
      b.label_class = v.class_id;
      if (is_look_alike_class(v.class_id) && rng.chance(knobs.vlm_confusion_rate)) {
        b.label_class = confused_class(v.class_id, rng);
      }
      emit(round, json, v.box.x1 + rng.normal(0, s * bw), v.box.y1 + rng.normal(0, s * bh),
           v.box.x2 + rng.normal(0, s * bw), v.box.y2 + rng.normal(0, s * bh), width, height, b);
    }
    const int hallucinated = rng.poisson(knobs.vlm_hallucination_rate);
    for (int h = 0; h < hallucinated; ++h) {
      const double w = rng.uniform(0.05, 0.3) * width, hh = rng.uniform(0.05, 0.4) * height;
      const double x = rng.uniform(0, width - w), y = rng.uniform(0, height - hh);
      VlmBox b;
      b.label_class = 1 + rng.below(static_cast<int>(kOrClassCount));
      emit(round, json, x, y, x + w, y + hh, width, height, b);
    }
    for (VlmBox& b : round.boxes) b.box.round = r;
    round.reply = "```json\n[" + json.str() + (round.boxes.empty() ? "]\n```" : "\n]\n```");
  }
  return rounds;
}

std::string vlm_prompt() {
  struct Context {
    int class_id;
    const char* spatial;
    const char* behaviour;  // people only
    const char* appearance;
  };
  static const Context contexts[] = {
      {kOperatingTable, "in the centre of the room, under the lamp", nullptr,
       "a long dark padded table on a single column"},
      {kPatient, "lying on the operating table", nullptr,
       "covered by a green surgical drape, only the head visible"},
      {kHeadSurgeon, "at the side of the operating table, at the operative site",
       "operates on the patient with both hands over the drape", "blue gown, cap and mask"},
      {kAssistantSurgeon, "across the table from the head surgeon",
       "assists the head surgeon, holds and passes instruments", "blue gown, cap and mask"},
      {kCirculatingNurse, "near the instrument table, away from the sterile field",
       "prepares and counts instruments, moves around the room", "blue gown, cap and mask"},
      {kAnaesthetist, "at the head end of the table, next to the anesthesia machine",
       "monitors the patient and the anesthesia machine", "teal scrubs, cap and mask"},
      {kAnesthesiaMachine, "at the head end of the table", nullptr,
       "a beige cabinet with a screen and gas cylinders"},
      {kInstrumentTable, "near the foot end of the table", nullptr,
       "a table covered with a blue sterile sheet and instruments"},
      {kSecondaryTable, "beside the operating table", nullptr,
       "a small metal table on a single stand"},
      {kMonitor, "on a stand facing the surgeons", nullptr, "a flat screen on a pole"},
      {kSurgicalLamp, "above the operating table, hanging from the ceiling", nullptr,
       "a round white lamp head on an articulated arm"},
      {kCArm, "beside the table during imaging, otherwise parked by the wall", nullptr,
       "a large white C-shaped X-ray device on a wheeled base"},
  };
  std::ostringstream p;
  p << "You are looking at one camera view of an operating room. Locate every instance of the "
       "following entities and output a bounding box and a label for each.\n\n";
  for (const Context& c : contexts) {
    p << "- " << or_class_names().at(c.class_id) << ": where: " << c.spatial;
    if (c.behaviour) p << "; behaviour: " << c.behaviour;
    p << "; appearance: " << c.appearance << "\n";
  }
  p << "\nAnswer in JSON as a list of {\"bbox_2d\": [x1, y1, x2, y2], \"label\": \"<entity>\"} "
       "with coordinates normalised to 0..1000. Use exactly the entity names above.\n";
  return p.str();
}

}  // namespace gslift::synth
