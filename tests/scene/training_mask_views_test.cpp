// training_mask_views: the one matching of a MaskSet's views to its capture that feature
// training, lifting and association share.
#include <catch2/catch.hpp>

#include "nodes/scene/masks.hpp"
#include "runtime/node.hpp"

using namespace gslift;

namespace {

// Views cam_0..cam_3 of 8x6 pixels, cam_2 held out.
Capture four_views() {
  Capture c;
  c.name = "four";
  for (int i = 0; i < 4; ++i) {
    View v;
    v.name = "cam_" + std::to_string(i);
    v.camera.width = 8;
    v.camera.height = 6;
    v.held_out = i == 2;
    c.views.push_back(v);
  }
  return c;
}

ViewMasks masks_of(const std::string& view, int count, int width = 8, int height = 6) {
  ViewMasks vm{view, {}};
  for (int k = 0; k < count; ++k) {
    Mask m;
    m.pixels = cv::Mat1b::zeros(height, width);
    vm.masks.push_back(m);
  }
  return vm;
}

}  // namespace

TEST_CASE("training_mask_views: training views only, in MaskSet order, with both indices") {
  MaskSet masks;
  masks.views = {masks_of("cam_3", 1), masks_of("cam_2", 2), masks_of("cam_0", 0)};
  const auto kept = training_mask_views(four_views(), masks);
  REQUIRE(kept.size() == 2);
  CHECK(kept[0].mask_view == 0);
  CHECK(kept[0].capture_view == 3);
  CHECK(kept[1].mask_view == 2);  // a training view without masks is still a training view
  CHECK(kept[1].capture_view == 0);
}

TEST_CASE("training_mask_views: masks that do not fit the capture are bad input") {
  MaskSet masks;
  masks.views = {masks_of("cam_0", 1)};
  SECTION("a view the capture lacks") {
    masks.views.push_back(masks_of("cam_9", 1));
    CHECK_THROWS_AS(training_mask_views(four_views(), masks), InputError);
  }
  SECTION("a mask of another size, even in a held-out view") {
    masks.views.push_back(masks_of("cam_2", 1, 6, 8));
    CHECK_THROWS_AS(training_mask_views(four_views(), masks), InputError);
  }
  SECTION("no training view has masks") {
    masks.views = {masks_of("cam_2", 1)};
    CHECK_THROWS_AS(training_mask_views(four_views(), masks), InputError);
  }
}
