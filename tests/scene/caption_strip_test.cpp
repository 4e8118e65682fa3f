// Every picture gslift writes names what it shows (issue 32): the caption strip and the
// side-by-side panels of nodes/scene/caption_strip.hpp, and a written label overlay carrying it.
#include <opencv2/imgproc.hpp>

#include "base/errors.hpp"
#include "nodes/scene/caption_strip.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/image_io.hpp"
#include "nodes/scene/label_maps.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

// Pixels of `strip` darker than mid grey: the text and the swatch borders.
int dark_pixels(const cv::Mat3b& strip) {
  int n = 0;
  for (int y = 0; y < strip.rows; ++y)
    for (int x = 0; x < strip.cols; ++x)
      n += strip(y, x)[0] + strip(y, x)[1] + strip(y, x)[2] < 384;
  return n;
}

}  // namespace

TEST_CASE("with_caption adds a strip of text and swatches under the untouched image") {
  const cv::Mat3b grey(40, 200, cv::Vec3b(90, 90, 90));
  const std::vector<LegendEntry> legend = {{"patient", cv::Vec3b(255, 0, 0)},
                                           {"monitor", cv::Vec3b(0, 255, 0)}};
  const cv::Mat3b out = with_caption(grey, "held-out view", legend);
  // One title line and one legend line of 16 pixels, a 4-pixel margin.
  CHECK(caption_strip_height(200, legend) == 36);
  CHECK(caption_strip_height(200, {}) == 20);
  REQUIRE(out.rows == 40 + 36);
  CHECK(out.cols == 200);
  CHECK(cv::norm(out(cv::Rect(0, 0, 200, 40)), grey, cv::NORM_INF) == 0);
  const cv::Mat3b strip = out(cv::Rect(0, 40, 200, 36));
  CHECK(dark_pixels(strip(cv::Rect(0, 0, 200, 16))) > 20);  // the title's letters
  int red = 0, green = 0;
  for (int y = 0; y < strip.rows; ++y)
    for (int x = 0; x < strip.cols; ++x) {
      red += strip(y, x) == cv::Vec3b(255, 0, 0);
      green += strip(y, x) == cv::Vec3b(0, 255, 0);
    }
  CHECK(red == 8 * 8);  // a 10-pixel swatch inside its 1-pixel border
  CHECK(green == 8 * 8);
}

TEST_CASE("a legend wider than the image wraps onto more lines") {
  std::vector<LegendEntry> legend;
  for (int k = 0; k < 12; ++k) legend.push_back({"class " + std::to_string(k), cv::Vec3b(0, 0, k)});
  const int narrow = caption_strip_height(120, legend), wide = caption_strip_height(2000, legend);
  CHECK(wide == 36);
  CHECK(narrow > wide);
  CHECK((narrow - 4) % 16 == 0);
}

TEST_CASE("side_by_side puts captioned panels of one height in a row") {
  const cv::Mat3b a(20, 30, cv::Vec3b(255, 0, 0)), b(40, 60, cv::Vec3b(0, 0, 255));
  const cv::Mat3b out = side_by_side({{"ground truth", a}, {"render", b}});
  CHECK(out.rows == 16 + 4 + 20);  // the caption line, the gap, the panels at the first's height
  CHECK(out.cols == 30 + 4 + 30);  // the second scaled to 20 rows is 30 wide
  CHECK(out(20, 0) == cv::Vec3b(255, 0, 0));
  CHECK(out(39, 63) == cv::Vec3b(0, 0, 255));
  CHECK(dark_pixels(out(cv::Rect(0, 0, out.cols, 16))) > 20);
  CHECK_THROWS_AS(side_by_side({}), InputError);
}

TEST_CASE("a written label overlay carries its legend strip") {
  Capture capture;
  View view;
  view.name = "cam_00";
  view.rgb = ImageSource::in_memory(cv::Mat3b(24, 64, cv::Vec3b(40, 40, 40)));
  capture.views.push_back(view);
  LabelMapSet maps;
  maps.views.push_back({"cam_00", cv::Mat1i(24, 64, 0)});
  maps.views[0].labels(cv::Rect(0, 0, 32, 24)) = 3;
  maps.labels = 3;
  const auto dir = test::scratch_dir("caption_label_overlay");
  write_label_map_files(maps, &capture, dir);
  const cv::Mat3b written = read_rgb(dir / "cam_00_overlay.png");
  const std::vector<LegendEntry> legend = {{"id 3", label_colour(3)}};
  REQUIRE(written.rows == 24 + caption_strip_height(64, legend));
  CHECK(dark_pixels(written(cv::Rect(0, 24, 64, written.rows - 24))) > 20);
  // The label labels must stay the map's size: they are data, read back by the eval nodes.
  CHECK(read_label_map(dir / "cam_00_labels.png").rows == 24);
}
