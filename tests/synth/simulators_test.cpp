// The simulated upstream models hit their configured rates over many samples, presets move the
// rates in the expected direction, and the encodings are exact.
#include <cmath>
#include <map>

#include <nlohmann/json.hpp>

#include "nodes/synth/depth_prior_simulator.hpp"
#include "nodes/synth/mask_boundary_noise.hpp"
#include "nodes/synth/or_scene.hpp"
#include "nodes/synth/pose_noise.hpp"
#include "nodes/synth/sam_auto_simulator.hpp"
#include "nodes/synth/sam_box_simulator.hpp"
#include "nodes/synth/synth_knobs.hpp"
#include "nodes/synth/vlm_simulator.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using namespace gslift::synth;

namespace {

// A 200x100 map with a head surgeon (id 1, left) touching a nurse (id 2, right) and a monitor
// (id 3) standing alone, on background 0.
cv::Mat toy_instances() {
  cv::Mat ids(100, 200, CV_32SC1, cv::Scalar(0));
  ids(cv::Rect(20, 20, 40, 60)).setTo(1);
  ids(cv::Rect(60, 20, 40, 60)).setTo(2);
  ids(cv::Rect(140, 30, 40, 40)).setTo(3);
  return ids;
}
const std::map<int, int> kToyClasses = {{1, kHeadSurgeon}, {2, kCirculatingNurse}, {3, kMonitor}};

}  // namespace

TEST_CASE("VLM simulation: miss, confusion and hallucination rates within tolerance") {
  SynthKnobs k;
  k.vlm_rounds = 20;
  k.vlm_miss_rate = 0.2;
  k.vlm_confusion_rate = 0.3;
  k.vlm_hallucination_rate = 0.5;
  k.vlm_jitter = 0.05;
  const auto visible = visible_instances(toy_instances(), kToyClasses, 0.001);
  REQUIRE(visible.size() == 3);
  CHECK(visible[0].box.x1 == 20.f);
  CHECK(visible[0].box.x2 == 60.f);
  int asked = 0, answered = 0, people = 0, confused = 0, monitor_confused = 0, hallucinated = 0;
  int rounds = 0;
  double jitter_sq = 0;
  int jitter_n = 0;
  for (uint64_t seed = 0; seed < 150; ++seed) {
    const auto result = simulate_vlm(visible, 200, 100, k, seed);
    for (const VlmRound& r : result) {
      ++rounds;
      asked += 3;
      for (const VlmBox& b : r.boxes) {
        if (b.source_instance == 0) {
          ++hallucinated;
          continue;
        }
        ++answered;
        if (is_look_alike_class(b.true_class)) {
          ++people;
          confused += b.label_class != b.true_class;
          CHECK(is_look_alike_class(b.label_class));
        } else {
          monitor_confused += b.label_class != b.true_class;
        }
        if (b.source_instance == 3) {
          // Left edge of the monitor (x1 = 140, width 40): sigma = 0.05 * 40 = 2 px.
          jitter_sq += std::pow(b.box.x1 - 140.0, 2);
          ++jitter_n;
        }
      }
    }
  }
  CHECK(1.0 - double(answered) / asked == Approx(0.2).margin(0.02));
  CHECK(double(confused) / people == Approx(0.3).margin(0.03));
  CHECK(monitor_confused == 0);
  CHECK(double(hallucinated) / rounds == Approx(0.5).margin(0.05));
  // Norm1000 rounding adds 0.2 px of uniform error: sigma^2 = 4 + 0.2^2/12 ~ 4.
  CHECK(std::sqrt(jitter_sq / jitter_n) == Approx(2.0).margin(0.15));
}

TEST_CASE("VLM reply is Qwen3-VL JSON in norm1000 coordinates inside a ```json fence") {
  SynthKnobs k;
  k.vlm_rounds = 1;
  k.vlm_miss_rate = 0;
  k.vlm_jitter = 0;
  k.vlm_confusion_rate = 0;
  k.vlm_hallucination_rate = 0;
  const auto rounds =
      simulate_vlm(visible_instances(toy_instances(), kToyClasses, 0), 200, 100, k, 1);
  const std::string& reply = rounds[0].reply;
  REQUIRE(reply.rfind("```json\n[", 0) == 0);
  REQUIRE(reply.size() > 4);
  CHECK(reply.substr(reply.size() - 4) == "\n```");
  const auto json = nlohmann::json::parse(reply.substr(8, reply.size() - 12));
  REQUIRE(json.size() == 3);
  for (const auto& e : json) {
    if (e["label"] != "monitor") continue;
    // Monitor box x 140..180 of 200, y 30..70 of 100 -> 700, 300, 900, 700.
    CHECK(e["bbox_2d"] == nlohmann::json({700, 300, 900, 700}));
  }
  CHECK(vlm_prompt().find("anesthesia machine") != std::string::npos);
}

TEST_CASE("SAM box simulation: best-covered instance, leak rate, wrong blob for empty boxes") {
  const cv::Mat ids = toy_instances();
  const std::vector<int> pixels = count_labels(ids, cv::Rect(0, 0, ids.cols, ids.rows));
  SynthKnobs k;
  k.sam_boundary_noise = 1.0;
  k.sam_leak_rate = 0.25;
  Box surgeon;
  surgeon.x1 = 18, surgeon.y1 = 18, surgeon.x2 = 62, surgeon.y2 = 82;
  int leaks = 0, n = 2000;
  double iou_sum = 0;
  RandomStream rng(5);
  for (int i = 0; i < n; ++i) {
    const SamBoxMask m = simulate_sam_box(surgeon, ids, pixels, k, rng);
    REQUIRE(m.instance == 1);
    if (m.leaked_into != 0) {
      CHECK(m.leaked_into == 2);
      ++leaks;
      continue;
    }
    const cv::Mat1b truth = ids == 1;
    iou_sum += double(cv::countNonZero(truth & m.mask)) / cv::countNonZero(truth | m.mask);
  }
  CHECK(double(leaks) / n == Approx(0.25).margin(0.03));
  // A 1-pixel boundary noise on a 40x60 box costs a few percent of IoU, not more.
  const double mean_iou = iou_sum / (n - leaks);
  CHECK(mean_iou > 0.9);
  CHECK(mean_iou < 0.995);

  Box empty;  // over background only
  empty.x1 = 110, empty.y1 = 5, empty.x2 = 135, empty.y2 = 95;
  const SamBoxMask blob = simulate_sam_box(empty, ids, pixels, k, rng);
  CHECK(blob.instance == 0);
  CHECK(cv::countNonZero(blob.mask) > 20);
  CHECK(cv::countNonZero(blob.mask(cv::Rect(0, 0, 100, 100))) == 0);  // stays near its box
}

TEST_CASE("SAM automatic masks: split, merge and fragment rates, parts at granularity 1") {
  // Instance 1 has two parts (rows 20..49 part 1, 50..79 part 2); 2 and 3 one part each.
  const cv::Mat ids = toy_instances();
  cv::Mat parts(ids.size(), CV_32SC1, cv::Scalar(0));
  parts.setTo(1, ids > 0);
  parts(cv::Rect(20, 50, 40, 30)).setTo(2);
  SynthKnobs k;
  k.sam_boundary_noise = 0;
  k.sam_auto_split_rate = 0.3;
  k.sam_auto_merge_rate = 0.2;
  k.sam_auto_fragments = 1.5;
  int splits = 0, merges_of_1 = 0, fragments = 0, gran1 = 0, views = 3000;
  for (int v = 0; v < views; ++v) {
    RandomStream rng(stream_seed(9, kSamAutoStream, v));
    for (const AutoMask& m : simulate_sam_auto(ids, parts, k, rng, 1e-3)) {
      if (m.kind == AutoMask::Kind::Fragment) ++fragments;
      if (m.granularity == 1) {
        ++gran1;
        continue;
      }
      if (m.kind == AutoMask::Kind::Part && m.mask(30, 30)) ++splits;  // part 1 of instance 1
      if (m.kind == AutoMask::Kind::Merged && m.mask(30, 30)) {
        ++merges_of_1;
        CHECK(m.mask(30, 80) != 0);  // merged with its touching neighbour, the nurse
        CHECK(m.mask(50, 160) == 0);
      }
    }
  }
  // Instance 1 is drawn first: merge with p = 0.2, else split with p = 0.3.
  CHECK(double(merges_of_1) / views == Approx(0.2).margin(0.02));
  CHECK(double(splits) / views == Approx(0.3).margin(0.025));
  CHECK(double(fragments) / views == Approx(1.5).margin(0.1));
  CHECK(gran1 == 2 * views);  // the two parts of instance 1, every view
}

TEST_CASE("presets order every failure rate easy < default < hard") {
  const SynthKnobs e = preset_knobs(SynthPreset::Easy), d = preset_knobs(SynthPreset::Default),
                   h = preset_knobs(SynthPreset::Hard);
  for (auto f :
       {&SynthKnobs::vlm_miss_rate, &SynthKnobs::vlm_jitter, &SynthKnobs::vlm_confusion_rate,
        &SynthKnobs::vlm_hallucination_rate, &SynthKnobs::sam_boundary_noise,
        &SynthKnobs::sam_leak_rate, &SynthKnobs::sam_auto_split_rate,
        &SynthKnobs::sam_auto_merge_rate, &SynthKnobs::sam_auto_fragments, &SynthKnobs::depth_noise,
        &SynthKnobs::depth_holes}) {
    CHECK(e.*f < d.*f);
    CHECK(d.*f < h.*f);
  }
  CHECK(h.pose_noise_deg > d.pose_noise_deg);
  CHECK_THROWS_WITH(parse_enum(std::string("medium"), preset_names(), "preset"),
                    Catch::Contains("'medium' is not one of {easy, default, hard}"));

  // And the simulated outputs follow: fewer VLM boxes are missed under easy than under hard.
  const auto visible = visible_instances(toy_instances(), kToyClasses, 0);
  auto answered = [&](const SynthKnobs& k) {
    int n = 0;
    for (uint64_t s = 0; s < 40; ++s)
      for (const auto& r : simulate_vlm(visible, 200, 100, k, s))
        for (const auto& b : r.boxes) n += b.source_instance != 0;
    return n;
  };
  CHECK(answered(e) > answered(d));
  CHECK(answered(d) > answered(h));
}

TEST_CASE("knobs are settable by name with checked values") {
  SynthKnobs k;
  set_knob(k, "vlm_miss_rate", "0.4");
  set_knob(k, "vlm_rounds", "3");
  set_knob(k, "shadows", "false");
  CHECK(k.vlm_miss_rate == 0.4);
  CHECK(k.vlm_rounds == 3);
  CHECK_FALSE(k.shadows);
  CHECK_THROWS_WITH(set_knob(k, "vlm_mis_rate", "0.1"), Catch::Contains("unknown synth knob"));
  CHECK_THROWS_WITH(set_knob(k, "vlm_miss_rate", "1.5"), Catch::Contains("outside [0, 1]"));
  CHECK_THROWS_WITH(set_knob(k, "vlm_rounds", "2.5"), Catch::Contains("not an integer"));
  CHECK_THROWS_WITH(set_knob(k, "depth_noise", "abc"), Catch::Contains("not a number"));
  for (const KnobField& info : synth_knob_table().fields()) {
    SynthKnobs copy;
    set_knob(copy, info.spec.name, knob_value(k, info));
    CHECK(knob_value(copy, info) == knob_value(k, info));
  }
}

TEST_CASE("depth prior: relative noise and hole fraction as configured") {
  cv::Mat1f depth(240, 320, 2.0f);
  RandomStream rng(3);
  const cv::Mat1f prior = simulate_depth_prior(depth, 0.05, 0.1, rng);
  double sum_sq = 0;
  int valid = 0;
  for (float d : prior) {
    if (d == 0) continue;
    ++valid;
    sum_sq += std::pow(d / 2.0 - 1.0, 2);
  }
  const double holes = 1.0 - double(valid) / depth.total();
  CHECK(holes == Approx(0.1).margin(0.03));
  // Half the variance is smooth (correlated over 32 px), so one image estimates it loosely.
  CHECK(std::sqrt(sum_sq / valid) == Approx(0.05).margin(0.012));
  RandomStream exact(3);
  CHECK(cv::countNonZero(simulate_depth_prior(depth, 0, 0, exact) != depth) == 0);
}

TEST_CASE("pose noise moves the camera centre and rotation by the configured sigmas") {
  Pose p;
  p.R = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix();
  p.t = Eigen::Vector3d(1, 2, 3);
  RandomStream rng(8);
  double ang_sq = 0, pos_sq = 0;
  const int n = 4000;
  for (int i = 0; i < n; ++i) {
    const Pose q = perturb_pose(p, 1.0, 0.02, rng);
    ang_sq += std::pow(Eigen::AngleAxisd(q.R * p.R.transpose()).angle() * 180 / M_PI, 2);
    pos_sq += (q.centre() - p.centre()).squaredNorm();
  }
  CHECK(std::sqrt(ang_sq / n) == Approx(1.0).margin(0.05));
  CHECK(std::sqrt(pos_sq / n / 3) == Approx(0.02).margin(0.001));
  const Pose same = perturb_pose(p, 0, 0, rng);
  CHECK(same.t.isApprox(p.t));
}

TEST_CASE("boundary noise keeps the mask near its boundary with the configured amplitude") {
  cv::Mat1b square(100, 100, uchar(0));
  square(cv::Rect(30, 30, 40, 40)).setTo(255);
  RandomStream rng(1);
  CHECK(cv::countNonZero(perturb_mask_boundary(square, 0, rng) != square) == 0);
  const cv::Mat1b noisy = perturb_mask_boundary(square, 2.0, rng);
  const int changed = cv::countNonZero(noisy != square);
  // Perimeter 160 px, mean |displacement| about 0.8 * 2 * (interpolated field std ~0.7) px.
  CHECK(changed > 80);
  CHECK(changed < 600);
  CHECK(cv::countNonZero(noisy(cv::Rect(0, 0, 20, 100))) == 0);  // nothing 10+ px away
}
