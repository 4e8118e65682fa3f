// The click's mask carried by automatic masks (mask_carry.hpp): which mask of the prompt's view a
// click takes, the rendered selection on hand-built blend weights, which masks of another view
// the selection covers, and the lifting in the prompt's own view on the two-blob scene.
#include "nodes/inference/mask_carry.hpp"

#include "base/errors.hpp"
#include "nodes/inference/selection_mask.hpp"
#include "tests/inference/query_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

cv::Mat1b box(cv::Size size, cv::Rect r) {
  cv::Mat1b m = cv::Mat1b::zeros(size);
  m(r) = 255;
  return m;
}

// Views named `names` with the query camera at the identity pose; the one named `held` held out.
Capture query_capture(std::initializer_list<const char*> names, const std::string& held) {
  Capture capture;
  for (const char* name : names) {
    View v;
    v.name = name;
    v.camera = test::query_camera();
    v.held_out = name == held;
    capture.views.push_back(v);
  }
  return capture;
}

}  // namespace

TEST_CASE("clicked mask: the mask holding the click that agrees best with the features' answer",
          "[inference][mask_carry]") {
  const cv::Size size(20, 10);
  // A table (columns 0-9) with a patient on it (columns 10-19): the coarse mask merges both, the
  // fine one is the table alone; a third mask (the patient) does not hold the click.
  const cv::Mat1b merged = box(size, {0, 0, 20, 10}), table = box(size, {0, 0, 10, 10}),
                  patient = box(size, {10, 0, 10, 10});
  // The features' answer: the table and two columns of the patient. IoU with the table 100/120,
  // with the merged mask 120/200.
  const cv::Mat1b answer = box(size, {0, 0, 12, 10});
  const cv::Mat1b got = clicked_mask({merged, table, patient}, {{3, 4}}, answer);
  CHECK(cv::countNonZero(got != table) == 0);
  // Every click must lie in the mask: clicks on both halves take the merged mask.
  CHECK(cv::countNonZero(clicked_mask({merged, table, patient}, {{3, 4}, {15, 4}}, answer) !=
                         merged) == 0);
  // Given with a click on the patient, the table's click never takes the merged mask, even where
  // the answer would prefer it (here it covers both halves: IoU 1 with the merged mask).
  const cv::Mat1b both = box(size, {0, 0, 20, 10});
  CHECK(cv::countNonZero(clicked_mask({merged, table, patient}, {{3, 4}}, both) != merged) == 0);
  CHECK(cv::countNonZero(clicked_mask({merged, table, patient}, {{3, 4}}, both, {{15, 4}}) !=
                         table) == 0);
  // No candidate at all: the answer's 8-connected piece under the click (two pieces here).
  cv::Mat1b two = box(size, {0, 0, 4, 4}) | box(size, {10, 5, 4, 4});
  const cv::Mat1b piece = clicked_mask({}, {{1, 1}}, two);
  CHECK(cv::countNonZero(piece) == 16);
  CHECK(piece(1, 1) == 255);
  CHECK(piece(6, 11) == 0);
  // Neither a mask nor the answer holds it: an empty mask of the view's size.
  const cv::Mat1b none = clicked_mask({}, {{5, 5}}, two);
  CHECK(none.size() == size);
  CHECK(cv::countNonZero(none) == 0);
}

TEST_CASE("clicked mask: a click in a gap of the masks is answered at the nearest held pixel",
          "[inference][mask_carry]") {
  const cv::Size size(20, 10);
  // A thin lamp arm (columns 2-4) and a monitor (columns 12-19); the masks leave columns 5-11
  // uncovered. The features' answer floods the wall behind (everything): the piece under the click
  // would be the whole view.
  const cv::Mat1b arm = box(size, {2, 0, 3, 10}), monitor = box(size, {12, 0, 8, 10});
  const cv::Mat1b flood = box(size, {0, 0, 20, 10});
  // Column 7 is 3 px from the arm (column 4) and 5 px from the monitor (column 12).
  CHECK(cv::countNonZero(clicked_mask({arm, monitor}, {{7, 5}}, flood) != arm) == 0);
  // Column 9: 5 px from the arm, 3 px from the monitor.
  CHECK(cv::countNonZero(clicked_mask({arm, monitor}, {{9, 5}}, flood) != monitor) == 0);
  // The answer is the arm's piece alone (the features found the object, its masks missed it):
  // the monitor's mask lies outside it and is not taken; the answer's piece stays.
  const cv::Mat1b compact = box(size, {6, 2, 3, 6});
  CHECK(cv::countNonZero(clicked_mask({arm, monitor}, {{7, 5}}, compact) != compact) == 0);
  CHECK(cv::countNonZero(clicked_mask({monitor}, {{7, 5}}, compact) != compact) == 0);
  // Snapped onto a mask holding another prompt's click, the merged-mask rule applies as to a
  // click inside it: here no mask is left, so the answer's piece at the snapped pixel.
  CHECK(cv::countNonZero(clicked_mask({monitor}, {{9, 5}}, flood, {{15, 5}}) != flood) == 0);
}

TEST_CASE("clicked mask: a merged mask with the other clicks' masks cut out",
          "[inference][mask_carry]") {
  const cv::Size size(20, 10);
  // The view's masks merged the table (columns 0-9) with the clicked patient (columns 10-19) and
  // have no mask of the table alone; the patient has its own (columns 10-19) and a part (its
  // head, columns 16-19). A fragment on the table (columns 0-2) does not hold the click.
  const cv::Mat1b merged = box(size, {0, 0, 20, 10}), patient = box(size, {10, 0, 10, 10}),
                  head = box(size, {16, 0, 4, 10}), fragment = box(size, {0, 0, 3, 10});
  // The features' answer spreads over the room: without the cut the click would take all of it.
  const cv::Mat1b answer = box(size, {0, 0, 20, 10});
  const cv::Mat1b got =
      clicked_mask({merged, patient, head, fragment}, {{5, 4}}, answer, {{15, 4}});
  CHECK(cv::countNonZero(got != box(size, {0, 0, 10, 10})) == 0);
  // Only the piece holding the click: a second piece of the merged mask left by the cut (the
  // patient's mask holds columns 10-14 here, so columns 15-19 stay) is not the table's.
  const cv::Mat1b middle = box(size, {10, 0, 5, 10});
  const cv::Mat1b left = clicked_mask({merged, middle}, {{5, 4}}, answer, {{12, 4}});
  CHECK(cv::countNonZero(left != box(size, {0, 0, 10, 10})) == 0);
  // Where no mask holds the other click alone, nothing is cut and the piece still holds it: the
  // answer's piece under the click, as without merged masks.
  const cv::Mat1b small = box(size, {0, 0, 6, 10});
  CHECK(cv::countNonZero(clicked_mask({merged}, {{3, 4}}, small, {{15, 4}}) != small) == 0);
}

TEST_CASE("rendered selection: a pixel is in where the selected weights reach the threshold",
          "[inference][mask_carry]") {
  // 3 x 1 pixels: pixel 0 = (g0 0.3, g1 0.4), pixel 1 = (g1 0.6), pixel 2 = (g2 0.5).
  const std::vector<uint32_t> offsets{0, 2, 3, 4}, ids{0, 1, 1, 2};
  const std::vector<float> weights{0.3f, 0.4f, 0.6f, 0.5f};
  const PixelRowsView rows{offsets.data(), ids.data(), weights.data()};
  const std::vector<cv::Mat1b> drawn = rendered_selections(rows, 3, 1, {{1, 1, 0}, {1, 0, 1}});
  REQUIRE(drawn.size() == 2);
  const cv::Mat1b &a = drawn[0], &b = drawn[1];
  CHECK(a(0, 0) == 255);  // 0.7
  CHECK(a(0, 1) == 255);  // 0.6
  CHECK(a(0, 2) == 0);    // g2 not selected
  CHECK(b(0, 0) == 0);    // 0.3
  CHECK(b(0, 1) == 0);    // 0
  CHECK(b(0, 2) == 255);  // 0.5: at the threshold counts
}

TEST_CASE("rendered selections: more selections than one word of bits, each its own sums",
          "[inference][mask_carry]") {
  // 2 x 1 pixels: pixel 0 = (g0 0.5, g1 0.25), pixel 1 = (g2 0.75). Selection k holds Gaussian
  // k % 3 and, for k >= 64 (the second word of bits), Gaussian 1 too.
  const std::vector<uint32_t> offsets{0, 2, 3}, ids{0, 1, 2};
  const std::vector<float> weights{0.5f, 0.25f, 0.75f};
  const PixelRowsView rows{offsets.data(), ids.data(), weights.data()};
  std::vector<std::vector<uint8_t>> selected(70, std::vector<uint8_t>(3, 0));
  for (size_t k = 0; k < selected.size(); ++k) {
    selected[k][k % 3] = 1;
    if (k >= 64) selected[k][1] = 1;
  }
  const std::vector<cv::Mat1b> drawn = rendered_selections(rows, 2, 1, selected, 0.6f);
  REQUIRE(drawn.size() == 70);
  for (size_t k = 0; k < drawn.size(); ++k) {
    INFO(k);
    // Pixel 0 reaches 0.6 only with g0 and g1 (0.75); pixel 1 with g2 (0.75).
    const bool both = k % 3 == 0 && k >= 64;
    CHECK(drawn[k](0, 0) == (both ? 255 : 0));
    CHECK(drawn[k](0, 1) == (k % 3 == 2 ? 255 : 0));
  }
}

TEST_CASE("covered masks: the union of the masks the selection covers mostly",
          "[inference][mask_carry]") {
  const cv::Size size(10, 10);
  const cv::Mat1b left = box(size, {0, 0, 5, 10}), right = box(size, {5, 0, 5, 10});
  // Covered: 30 of left's 50 pixels (0.6), 20 of right's 50 (0.4).
  const cv::Mat1b covered = box(size, {2, 0, 5, 10});
  CHECK(cv::countNonZero(covered_masks({left, right}, covered, 0.5) != left) == 0);
  CHECK(cv::countNonZero(covered_masks({left, right}, covered, 0.4) != (left | right)) == 0);
  CHECK(covered_masks({left, right}, covered, 0.7).empty());
  CHECK(covered_masks({}, covered, 0.5).empty());
}

TEST_CASE("containing masks: a mask holding the selection, and no other's, is the object's",
          "[inference][mask_carry]") {
  const cv::Size size(20, 10);
  // A table (columns 0-9) whose leg (columns 0-4) was the click's mask, a patient beside it
  // (columns 10-19), and a coarse mask merging both. The click's selection rendered here: columns
  // 1-4 (40 pixels); the patient's prompt's: columns 12-17 (60 pixels).
  const cv::Mat1b table = box(size, {0, 0, 10, 10}), leg = box(size, {0, 0, 5, 10}),
                  patient = box(size, {10, 0, 10, 10}), merged = box(size, {0, 0, 20, 10});
  const cv::Mat1b own = box(size, {1, 0, 4, 10}), other = box(size, {12, 0, 6, 10});
  // The table and the leg hold all of it; the merged mask too, but all of the patient's as well.
  CHECK(cv::countNonZero(containing_masks({table, leg, patient, merged}, own, {other}, 0.5) !=
                         table) == 0);
  // Without the other prompt the merged mask holds the selection and no one else's.
  CHECK(cv::countNonZero(containing_masks({table, merged}, own, {}, 0.5) != merged) == 0);
  // A mask from column 3 holds 20 of the 40 pixels: in at 0.5, out at 0.6.
  const cv::Mat1b right_half = box(size, {3, 0, 7, 10});
  CHECK(cv::countNonZero(containing_masks({right_half}, own, {other}, 0.5) != right_half) == 0);
  CHECK(containing_masks({right_half}, own, {other}, 0.6).empty());
  CHECK(containing_masks({table}, cv::Mat1b::zeros(size), {other}, 0.5).empty());

  // Carried: covered_masks takes the leg (40 of its 50 pixels covered) and not the table (40 of
  // 100); containment adds the table.
  const std::vector<cv::Mat1b> candidates = {table, leg, patient, merged};
  CHECK(cv::countNonZero(carried_masks(candidates, own, {other}, 0.5, 0) != leg) == 0);
  CHECK(cv::countNonZero(carried_masks(candidates, own, {other}, 0.5, 0.5) != table) == 0);
  // The patient's prompt: its selection covers 60 of the patient's 100 pixels, and the merged
  // mask holds the table's selection too.
  CHECK(cv::countNonZero(carried_masks(candidates, other, {own}, 0.5, 0.5) != patient) == 0);
  CHECK(carried_masks(candidates, cv::Mat1b::zeros(size), {other}, 0.5, 0.5).empty());
  // Alone (no other selection), the leg's click takes the merged mask too.
  CHECK(cv::countNonZero(carried_masks(candidates, own, {}, 0.5, 0.5) != merged) == 0);
}

TEST_CASE("stand-in masks: the click's view's masks that share no pixel with its own masks",
          "[inference][mask_carry]") {
  const cv::Size size(30, 10);
  // A table (columns 0-9) with its leg (columns 0-4), a patient (10-19) merged with the table by
  // a coarse mask, a lamp (22-29) alone, and a fragment on the lamp (24-25, rows 2-3). The click
  // is on the leg, whose mask is the click's own.
  const cv::Mat1b table = box(size, {0, 0, 10, 10}), leg = box(size, {0, 0, 5, 10}),
                  patient = box(size, {10, 0, 10, 10}), merged = box(size, {0, 0, 20, 10}),
                  lamp = box(size, {22, 0, 8, 10}), fragment = box(size, {24, 2, 2, 2});
  const std::vector<cv::Mat1b> candidates = {table, leg, patient, merged, lamp, fragment};
  // The merged mask holds the click, so the patient (part of it) is no stand-in: only the lamp
  // and the fragment on it are.
  CHECK(stand_in_masks(candidates, leg, {{2, 5}}) == std::vector<size_t>{4, 5});
  // Without the merged mask the patient is another object too.
  CHECK(stand_in_masks({table, leg, patient, lamp}, leg, {{2, 5}}) == std::vector<size_t>{2, 3});
  // The click's own mask counts even where no candidate holds the click (a gap click answered
  // at the nearest mask): the lamp's pixels are taken by it here.
  CHECK(stand_in_masks({table, lamp}, lamp, {{20, 5}}) == std::vector<size_t>{0});

  // Carried in another view where the leg's selection is columns 1-4 and the lamp's columns
  // 23-28: alone, the merged mask there holds the leg's selection and is taken; the lamp's
  // stand-in does not stop it (the merged mask holds none of the lamp), the patient's would.
  const cv::Mat1b own = box(size, {1, 0, 4, 10}), lamp_seen = box(size, {23, 0, 6, 10}),
                  patient_seen = box(size, {12, 0, 6, 10});
  CHECK(cv::countNonZero(carried_masks({table, merged}, own, {lamp_seen}, 0.5, 0.5) != merged) ==
        0);
  CHECK(cv::countNonZero(carried_masks({table, merged}, own, {patient_seen}, 0.5, 0.5) != table) ==
        0);
}

TEST_CASE("masks carried: the prompt view's mask lifted there alone, masks by training view",
          "[inference][mask_carry]") {
  const GaussianModel model = test::two_blobs();
  const Capture capture = query_capture({"train", "test"}, "test");
  const cv::Size size(capture.views[0].camera.width, capture.views[0].camera.height);
  // Prompt 0 = the left half of the training view, prompt 1 = the right half of it.
  const cv::Mat1b left = box(size, {0, 0, size.width / 2, size.height});
  const std::vector<std::vector<uint8_t>> lifted =
      lift_in_own_views(model, capture, {0, 0}, {left, ~left}, 0.0);
  CHECK(lifted[0] == std::vector<uint8_t>{1, 0});
  CHECK(lifted[1] == std::vector<uint8_t>{0, 1});
  // The left blob, rendered (alpha >= 0.5 within about 5 px of its centre), covers a few percent
  // of the left mask and none of the right one.
  const RenderCache w = render_weights(model, capture.views[0].camera, Pose{});
  const cv::Mat1b drawn =
      rendered_selections(w.pixel_rows(), size.width, size.height, {lifted[0]})[0];
  CHECK(cv::countNonZero(drawn & left) > 0.02 * cv::countNonZero(left));
  CHECK(cv::countNonZero(drawn & ~left) == 0);
  CHECK(cv::countNonZero(covered_masks({left, ~left}, drawn, 0.02) != left) == 0);
  MaskSet masks;
  masks.views.push_back({"train", {{left, "a"}, {~left, "b"}}});
  const auto by_view = masks_by_training_view(capture, masks);
  REQUIRE(by_view.size() == 2);
  CHECK(by_view[0].size() == 2);
  CHECK(by_view[1].empty());
  // Masks of a held-out view never become candidates: training_mask_views' rule.
  masks.views.push_back({"test", {{left, "a"}}});
  CHECK(masks_by_training_view(capture, masks)[1].empty());
  masks.views.push_back({"nowhere", {{left, "a"}}});
  CHECK_THROWS_AS(masks_by_training_view(capture, masks), InputError);
}

TEST_CASE("reference masks by label: the union per label, all-zero where absent, none held out",
          "[inference][mask_carry]") {
  const Capture capture = query_capture({"a", "b", "held", "bare"}, "held");
  const cv::Size size(capture.views[0].camera.width, capture.views[0].camera.height);
  const cv::Mat1b left = box(size, {0, 0, 4, 3}), right = box(size, {10, 2, 5, 5});
  MaskSet masks;
  // View a: the fox in two pieces (a tracker's mask split by an occluder) and a chair; view b: the
  // chair alone (the fox out of sight); the held-out view's fox never votes; view 'bare' has none.
  masks.views.push_back({"a", {{left, "fox"}, {right, "fox"}, {right, "chair"}}});
  masks.views.push_back({"b", {{left, "chair"}}});
  masks.views.push_back({"held", {{left, "fox"}}});
  const auto given = labelled_masks_by_training_view(capture, masks, {"fox", "chair"});
  REQUIRE(given.size() == 4);
  CHECK(cv::countNonZero(given[0][0] != (left | right)) == 0);
  CHECK(cv::countNonZero(given[0][1] != right) == 0);
  REQUIRE(given[1][0].size() == size);
  CHECK(cv::countNonZero(given[1][0]) == 0);
  CHECK(cv::countNonZero(given[1][1] != left) == 0);
  CHECK(given[2][0].empty());
  CHECK(given[3][0].empty());
  CHECK(given[3][1].empty());
  // A label shown only in the held-out view, or nowhere, is a misnamed prompt: an error, not an
  // empty selection.
  CHECK_THROWS_WITH(labelled_masks_by_training_view(capture, masks, {"fox", "dog"}),
                    Catch::Contains("'dog'"));
  masks.views[0].masks.resize(1);
  masks.views[0].masks[0].label = "chair";
  CHECK_THROWS_WITH(labelled_masks_by_training_view(capture, masks, {"fox"}),
                    Catch::Contains("'fox'"));
  masks.views.push_back({"nowhere", {{left, "fox"}}});
  CHECK_THROWS_AS(labelled_masks_by_training_view(capture, masks, {"chair"}), InputError);
}
