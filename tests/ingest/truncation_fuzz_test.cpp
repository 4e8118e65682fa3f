// Every prefix of a valid file either parses or throws InputError naming the file: no crash, no
// other exception type, whatever byte a download or a disk-full write stopped at.
#include <fstream>
#include <random>

#include "nodes/ingest/capture_loader.hpp"
#include "nodes/ingest/coco_rle.hpp"
#include "nodes/ingest/sam_masks.hpp"
#include "nodes/ingest/vlm_reply.hpp"
#include "runtime/node.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using Catch::Matchers::Contains;

namespace {

template <class Parse>
void each_prefix_parses_or_names(const std::string& text, const std::string& name, Parse parse) {
  for (size_t len = 0; len <= text.size(); ++len) {
    INFO(name << " cut at " << len << ": " << text.substr(0, len));
    try {
      parse(text.substr(0, len));
    } catch (const InputError& e) {
      CHECK_THAT(e.what(), Contains(name));
    }
  }
}

}  // namespace

TEST_CASE("truncated VLM replies") {
  VlmFrame frame;
  frame.image_width = 640;
  frame.image_height = 480;
  const std::string reply =
      "Here:\n```json\n[{\"bbox_2d\": [10, 20, 300, 400], \"label\": \"scrub \\\"nurse\\\"\"},\n"
      " {\"bbox\": [1, 2, 3, 4], \"label\": \"lamp\", \"score\": 0.5}]\n```\ndone";
  each_prefix_parses_or_names(reply, "round_1.txt", [&](const std::string& t) {
    parse_vlm_reply(t, frame, 1, "vlm/cam_00/round_1.txt");
  });
}

TEST_CASE("truncated SAM mask files") {
  const std::string autos =
      R"([{"segmentation": {"size": [2, 3], "counts": "231"}, "predicted_iou": 0.9,)"
      R"( "granularity": 1}, {"segmentation": {"size": [2, 3], "counts": [0, 6]}}])";
  each_prefix_parses_or_names(autos, "a.json",
                              [](const std::string& t) { parse_sam_auto_masks(t, "a.json"); });
  const std::string boxes = R"([null, {"size": [2, 3], "counts": "231"}])";
  each_prefix_parses_or_names(boxes, "b.json",
                              [](const std::string& t) { parse_sam_box_masks(t, "b.json"); });
}

TEST_CASE("random RLE strings decode or fail cleanly") {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 2000; ++trial) {
    std::string s(rng() % 12, ' ');
    for (char& c : s) c = static_cast<char>(40 + rng() % 80);  // around the 48..111 alphabet
    try {
      rle_decode(rle_counts_from_string(s, "r.json"), 3, 4, "r.json");
    } catch (const InputError& e) {
      CHECK_THAT(e.what(), Contains("r.json"));
    }
  }
}

TEST_CASE("truncated transforms.json") {
  const auto dir = test::scratch_dir("fuzz_transforms");
  const std::string json =
      R"({"fl_x": 5, "w": 4, "h": 2, "frames": [{"file_path": "a.png", "transform_matrix": )"
      R"([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}]})";
  std::ofstream(dir / "a.png") << "";  // never decoded: w and h are given
  each_prefix_parses_or_names(json, "transforms.json", [&](const std::string& t) {
    std::ofstream(dir / "transforms.json") << t;
    load_capture(dir / "transforms.json");
  });
}
