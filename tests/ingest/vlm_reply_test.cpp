#include "nodes/ingest/vlm_reply.hpp"

#include "runtime/node.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using Catch::Matchers::Contains;

namespace {

VlmFrame frame_640x480(VlmCoords coords) {
  VlmFrame f;
  f.coords = coords;
  f.image_width = 640;
  f.image_height = 480;
  return f;
}

}  // namespace

TEST_CASE("VLM reply: fences, prose, norm1000 scaling, clamping and degenerate boxes") {
  const std::string reply =
      "Sure! Here are the objects:\n```json\n[\n"
      "  {\"bbox_2d\": [100, 200, 500, 600], \"label\": \"surgeon\"},\n"
      "  {\"bbox_2d\": [300, 300, 300, 400], \"label\": \"line\"},\n"
      "  {\"bbox\": [900, 900, 1200, 1000], \"label\": \"lamp\", \"score\": 0.5}\n"
      "]\n```\nLet me know if you need more [help].";
  const auto boxes = parse_vlm_reply(reply, frame_640x480(VlmCoords::Norm1000), 3, "r.txt");
  REQUIRE(boxes.size() == 2);
  // x * 640 / 1000, y * 480 / 1000
  CHECK(boxes[0].x1 == Approx(64));
  CHECK(boxes[0].y1 == Approx(96));
  CHECK(boxes[0].x2 == Approx(320));
  CHECK(boxes[0].y2 == Approx(288));
  CHECK(boxes[0].label == "surgeon");
  CHECK(boxes[0].round == 3);
  CHECK(boxes[0].source_index == 0);
  // Clamped to the image; the zero-width box at index 1 was dropped.
  CHECK(boxes[1].x1 == Approx(576));
  CHECK(boxes[1].x2 == 640);
  CHECK(boxes[1].y2 == 480);
  CHECK(boxes[1].source_index == 2);
  CHECK(boxes[1].score == 0.5f);
}

TEST_CASE("VLM reply: resized_abs and pixel coordinates, single object") {
  VlmFrame resized = frame_640x480(VlmCoords::ResizedAbs);
  resized.input_width = 320;
  resized.input_height = 240;
  const auto a =
      parse_vlm_reply("[{\"bbox_2d\": [10, 20, 30, 40], \"label\": \"a\"}]", resized, 0, "r.txt");
  REQUIRE(a.size() == 1);
  CHECK(a[0].x1 == 20);
  CHECK(a[0].y2 == 80);

  VlmFrame pixels = frame_640x480(VlmCoords::Pixels);
  pixels.pixel_scale = 0.5;  // the capture was loaded at half resolution
  const auto b = parse_vlm_reply(
      "The box is {\"bbox_2d\": [10, 20, 30, 40], \"label\": \"a]{b\"} as asked.", pixels, 1, "r");
  REQUIRE(b.size() == 1);
  CHECK(b[0].x1 == 5);
  CHECK(b[0].y2 == 20);
  CHECK(b[0].label == "a]{b");

  CHECK(parse_vlm_reply("```json\n[]\n```", pixels, 0, "r").empty());
}

TEST_CASE("malformed VLM replies give InputError naming the file and round") {
  const char* bad[] = {
      "I cannot see any objects.",                        // no JSON value
      "```json\n[{\"bbox_2d\": [1, 2, 3, 4], \"label\"",  // unterminated
      "[{\"bbox_2d\": [1, 2, 3], \"label\": \"a\"}]",     // 3 coordinates
      "[{\"bbox_2d\": [1, 2, 3, \"4\"]}]",                // non-number
      "[{\"bbox_2d\": [1, 2, 3, 4],}]",                   // invalid JSON
      "[[1, 2, 3, 4]]",                                   // not an object
      "[{\"label\": \"a\"}]",                             // no box
  };
  for (const char* text : bad) {
    INFO(text);
    CHECK_THROWS_AS(
        parse_vlm_reply(text, frame_640x480(VlmCoords::Norm1000), 2, "vlm/a/round_2.txt"),
        InputError);
    CHECK_THROWS_WITH(
        parse_vlm_reply(text, frame_640x480(VlmCoords::Norm1000), 2, "vlm/a/round_2.txt"),
        Contains("vlm/a/round_2.txt") && Contains("round 2"));
  }
  VlmFrame no_size = frame_640x480(VlmCoords::ResizedAbs);
  CHECK_THROWS_WITH(parse_vlm_reply("[]", no_size, 0, "r.txt"), Contains("input size"));
}
