#include "nodes/ingest/coco_rle.hpp"

#include <random>

#include "runtime/node.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using Catch::Matchers::Contains;
using Counts = std::vector<uint32_t>;

TEST_CASE("RLE runs go down the columns and start with background") {
  // 0 1 1
  // 0 1 0   column-major: 0 0 | 1 1 1 | 0 -> counts 2 3 1
  cv::Mat1b m(2, 3);
  m << 0, 255, 255, 0, 255, 0;
  CHECK(rle_encode(m) == Counts{2, 3, 1});
  CHECK(cv::norm(rle_decode({2, 3, 1}, 2, 3, "x"), m, cv::NORM_INF) == 0);
  // A mask whose first pixel is set starts with an empty background run.
  cv::Mat1b full(2, 2, uchar(1));
  CHECK(rle_encode(full) == Counts{0, 4});
  CHECK(cv::countNonZero(rle_decode({0, 4}, 2, 2, "x")) == 4);
}

TEST_CASE("RLE strings: hand-computed golden values of maskApi.c's rleToString") {
  // Small counts are one character 48 + count.
  CHECK(rle_counts_to_string({3, 2, 5}) == "325");
  // 40 = 8 + 1 * 32: group 8 with the continuation bit (8 | 32 = 40 -> 'X'), then 1 -> '1'.
  CHECK(rle_counts_to_string({5, 40}) == "5X1");
  // 16 has bit 0x10 set, which would read as a sign: it needs a second, zero group ('`', '0').
  CHECK(rle_counts_to_string({16}) == "`0");
  // The fourth count is stored as 1 - 3 = -2: one group 30 (0b11110, sign bit set) -> 'N'.
  CHECK(rle_counts_to_string({2, 3, 4, 1}) == "234N");
  // 100 = 4 + 3 * 32 -> 'T' (4 | 32 + 48 = 84), '3'.
  CHECK(rle_counts_to_string({0, 100, 0}) == "0T30");

  CHECK(rle_counts_from_string("325", "x") == Counts{3, 2, 5});
  CHECK(rle_counts_from_string("5X1", "x") == Counts{5, 40});
  CHECK(rle_counts_from_string("`0", "x") == Counts{16});
  CHECK(rle_counts_from_string("234N", "x") == Counts{2, 3, 4, 1});
  CHECK(rle_counts_from_string("0T30", "x") == Counts{0, 100, 0});
}

TEST_CASE("RLE round trips on random masks in both count forms") {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 50; ++trial) {
    const int h = 1 + rng() % 40, w = 1 + rng() % 40;
    cv::Mat1b m(h, w);
    // Blobby masks: long runs and large deltas, not just salt and pepper.
    const int cx = rng() % w, cy = rng() % h, r = 1 + rng() % 20;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        m(y, x) =
            ((x - cx) * (x - cx) + (y - cy) * (y - cy) < r * r) != (rng() % 50 == 0) ? 255 : 0;
    const Counts counts = rle_encode(m);
    const std::string s = rle_counts_to_string(counts);
    REQUIRE(rle_counts_from_string(s, "x") == counts);
    const cv::Mat1b back = rle_decode_json(nlohmann::json{{"size", {h, w}}, {"counts", s}}, "x");
    REQUIRE(cv::norm(back, m, cv::NORM_INF) == 0);
    const cv::Mat1b back_list =
        rle_decode_json(nlohmann::json{{"size", {h, w}}, {"counts", counts}}, "x");
    REQUIRE(cv::norm(back_list, m, cv::NORM_INF) == 0);
  }
}

TEST_CASE("malformed RLE gives InputError naming the source") {
  CHECK_THROWS_WITH(rle_decode({2, 3}, 2, 3, "masks.json mask 4"),
                    Contains("masks.json mask 4") && Contains("sum to 5"));
  CHECK_THROWS_WITH(rle_decode_json(nlohmann::json{{"size", {2, 3}}, {"counts", "34"}}, "f.json"),
                    Contains("f.json"));
  CHECK_THROWS_WITH(rle_counts_from_string("3X", "f.json"), Contains("f.json"));  // cut short
  CHECK_THROWS_WITH(rle_counts_from_string("3 4", "f.json"), Contains("f.json"));
  // 'G' = 48 + 23 = 0b10111: a single group with the sign bit, i.e. 23 - 32 = -9.
  CHECK_THROWS_WITH(rle_counts_from_string("55G", "f.json"), Contains("f.json") && Contains("-9"));
  CHECK_THROWS_WITH(rle_decode_json(nlohmann::json{{"size", {2}}, {"counts", "6"}}, "f.json"),
                    Contains("f.json") && Contains("size"));
  CHECK_THROWS_WITH(
      rle_decode_json(nlohmann::json{{"size", {1, 2}}, {"counts", {1, -1}}}, "f.json"),
      Contains("f.json"));
}
