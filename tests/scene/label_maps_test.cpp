#include "nodes/scene/label_maps.hpp"

#include <filesystem>

#include <catch2/catch.hpp>

#include "nodes/scene/image_io.hpp"

using namespace gslift;

// Gaga's uint8 maps wrap past 255 ids; ours are 32-bit in memory and 16-bit on disk: a map with
// 320 distinct ids (one per pixel of a 20x16 image) comes back exactly, and 70000 is refused.
TEST_CASE("label maps with more than 255 ids round-trip through the 16-bit PNG") {
  LabelMapSet set;
  cv::Mat1i ids(16, 20);
  for (int k = 0; k < 320; ++k) ids(k / 20, k % 20) = k + 1;
  set.views.push_back({"v0", ids});
  set.labels = 320;
  const auto dir = std::filesystem::temp_directory_path() / "gslift_label_maps_test";
  std::filesystem::create_directories(dir);
  write_label_map_files(set, nullptr, dir);
  const cv::Mat back = read_label_map(dir / "v0_labels.png", false);
  REQUIRE(back.type() == CV_32SC1);
  CHECK(cv::countNonZero(back != ids) == 0);
  double top = 0;
  cv::minMaxLoc(back, nullptr, &top);
  CHECK(top == 320);
  set.views[0].labels(0, 0) = 70000;
  CHECK_THROWS(write_label_map_files(set, nullptr, dir));
  std::filesystem::remove_all(dir);
}
