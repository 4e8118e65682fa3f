// Prompt selection on a hand-built feature set: two visible blobs (query_scene.hpp) with features
// e1 (left) and e2 (right), and Gaussians outside the view whose features are known cosines away.
#include "nodes/inference/prompt_segmentation.hpp"

#include <cmath>

#include <opencv2/imgproc.hpp>

#include "base/errors.hpp"
#include "tests/inference/query_scene.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

// Gaussian: 0 left blob e1, 1 right blob e2, 2 off-screen (0.9, 0.1, 0): cos 0.994 with e1,
// 3 off-screen (0.5, 0.866, 0): cos 0.5 with e1 and 0.866 with e2, 4..11 off-screen e3.
GaussianModel feature_scene() {
  GaussianModel m = test::two_blobs();
  m.resize(12);
  m.instance_ids.clear();
  m.feature_dim = 3;
  m.features.assign(12 * 3, 0.f);
  const float f[4][3] = {{1, 0, 0}, {0, 1, 0}, {0.9f, 0.1f, 0}, {0.5f, 0.8660254f, 0}};
  for (int g = 0; g < 12; ++g) {
    for (int c = 0; c < 3; ++c) m.features[3 * g + c] = g < 4 ? f[g][c] : (c == 2 ? 2.f : 0.f);
    if (g >= 2) {
      m.means[3 * g] = 5.f + g;  // far right of the 64-px view: never drawn
      m.means[3 * g + 2] = 2.f;
      m.opacity_logits[g] = 4.f;
    }
  }
  return m;
}

Capture one_view() {
  Capture c;
  View v;
  v.name = "v0";
  v.camera = test::query_camera();
  c.views.push_back(v);
  return c;
}

std::vector<int> selected(const PromptSelection& s) {
  std::vector<int> out;
  for (size_t g = 0; g < s.selected.size(); ++g)
    if (s.selected[g]) out.push_back(static_cast<int>(g));
  return out;
}

Prompt point(std::vector<cv::Point> pos, std::vector<cv::Point> neg = {}) {
  Prompt p;
  p.name = "left";
  p.view = "v0";
  p.positive = std::move(pos);
  p.negative = std::move(neg);
  return p;
}

}  // namespace

TEST_CASE("point prompt: best positive cosine above tau and above the best negative") {
  const GaussianModel model = feature_scene();
  const Capture capture = one_view();
  PromptOptions o;  // fixed tau 0.75
  PromptSegmenter seg(model, capture, o);
  // A click on the left blob (pixel column 17) selects it and the off-screen Gaussian 2: the
  // selection reaches Gaussians the view never shows, through their features.
  PromptSelection s = seg.select(point({{17, 24}}));
  CHECK(selected(s) == std::vector<int>{0, 2});
  CHECK(s.score[0] == Approx(1).margin(1e-4));
  CHECK(s.score[2] == Approx(0.9 / std::sqrt(0.82)).margin(1e-4));
  CHECK(s.score[3] == Approx(0.5).margin(1e-4));
  CHECK(s.positive_queries == 1);
  // tau 0.4 admits Gaussian 3 (cos 0.5) ... unless a negative click on the right blob beats it
  // (S_n = 0.866 > S_p = 0.5).
  o.tau = 0.4;
  PromptSegmenter low(model, capture, o);
  CHECK(selected(low.select(point({{17, 24}}))) == std::vector<int>{0, 2, 3});
  CHECK(selected(low.select(point({{17, 24}}, {{47, 24}}))) == std::vector<int>{0, 2});
  // Adaptive tau: the mean best positive score, (1 + 0.9939 + 0.5 + 0 x 9) / 12 = 0.2078.
  o.threshold = PromptThreshold::Adaptive;
  PromptSegmenter adaptive(model, capture, o);
  s = adaptive.select(point({{17, 24}}));
  CHECK(s.threshold == Approx((1 + 0.9 / std::sqrt(0.82) + 0.5) / 12).margin(1e-4));
  CHECK(selected(s) == std::vector<int>{0, 2, 3});
}

TEST_CASE("scribble, mask and SAM-style prompts") {
  const GaussianModel model = feature_scene();
  const Capture capture = one_view();
  PromptOptions o;
  o.tau = 0.4;
  PromptSegmenter seg(model, capture, o);
  // Strokes across each blob: K-means queries e1 (positive) and e2 (negative).
  Prompt scribble = point({{14, 24}, {20, 24}}, {{44, 24}, {50, 24}});
  scribble.kind = PromptKind::Scribble;
  CHECK(selected(seg.select(scribble)) == std::vector<int>{0, 2});
  // A disc on the left blob as a mask prompt: K-means positives only, so Gaussian 3 (0.5) passes
  // tau 0.4 ...
  Prompt mask = point({});
  mask.kind = PromptKind::Mask;
  mask.mask = cv::Mat1b::zeros(48, 64);
  cv::circle(mask.mask, {17, 24}, 6, cv::Scalar(255), -1);
  PromptSelection s = seg.select(mask);
  CHECK(selected(s) == std::vector<int>{0, 2, 3});
  CHECK(s.negative_queries == 0);
  // ... until the outside of the mask gives negatives: with the mask = the left half of the view
  // (every pixel the left blob reaches), the right blob's e2 beats it. With a tight mask the
  // object's rendered fringe outside it would become a negative query of the object itself.
  Prompt half = mask;
  half.mask = cv::Mat1b(48, 64, uint8_t(0));  // a new buffer (assigning zeros() would write into
                                              // the one shared with mask.mask)
  half.mask(cv::Rect(0, 0, 32, 48)).setTo(255);
  o.mask_negatives = true;
  PromptSegmenter with_negatives(model, capture, o);
  s = with_negatives.select(half);
  CHECK(selected(s) == std::vector<int>{0, 2});
  CHECK(s.negative_queries > 0);
  // Validation by the mask: at tau -0.5 the disc selects every Gaussian; mask_validate drops the
  // right blob (its centre projects to column 47, outside the disc) and keeps the off-screen
  // ones, which the view cannot check.
  o.tau = -0.5;
  o.mask_negatives = false;
  PromptSegmenter loose(model, capture, o);
  CHECK(selected(loose.select(mask)).size() == 12);
  o.mask_validate = true;
  PromptSegmenter validated(model, capture, o);
  s = validated.select(mask);
  CHECK(selected(s) == std::vector<int>{0, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11});
  CHECK(s.count == 11);
  // SAM-style: the pooled query (e1) covers the whole disc in 2D, so it is accepted; tau_SAM =
  // mean + std of <f_g, q> over the 12 Gaussians = 0.2078 + 0.3786 = 0.586: Gaussian 3 (0.5)
  // stays out even at tau 0.4.
  mask.kind = PromptKind::Sam;
  s = seg.select(mask);
  CHECK(s.pooled);
  CHECK(s.threshold == Approx(0.586).margin(2e-3));
  CHECK(selected(s) == std::vector<int>{0, 2});
}

TEST_CASE("bad prompts are InputErrors naming what is wrong") {
  const GaussianModel model = feature_scene();
  const Capture capture = one_view();
  PromptSegmenter seg(model, capture, {});
  Prompt p = point({{64, 10}});
  CHECK_THROWS_AS(seg.select(p), InputError);  // outside the 64x48 view
  p = point({{1, 1}});
  p.view = "nope";
  CHECK_THROWS_AS(seg.select(p), InputError);
  p = point({});
  p.kind = PromptKind::Mask;
  p.mask = cv::Mat1b::zeros(48, 64);
  CHECK_THROWS_AS(seg.select(p), InputError);          // empty mask
  CHECK_THROWS_AS(seg.select(point({})), InputError);  // no positive pixel
  GaussianModel plain = test::two_blobs();
  CHECK_THROWS_AS(PromptSegmenter(plain, capture, {}), InputError);  // no features
}

TEST_CASE("overlapping selections go to the prompt that scores highest") {
  PromptSelection a, b;
  a.selected = {1, 1, 0, 0};
  a.score = {0.9f, 0.8f, 0.1f, 0.f};
  b.selected = {0, 1, 1, 0};
  b.score = {0.2f, 0.85f, 0.9f, 0.f};
  CHECK(selection_instance_ids({a, b}) == std::vector<int32_t>{0, 1, 1, -1});
}

TEST_CASE("prompts from reference masks: a point inside even a non-convex mask") {
  MaskSet ref;
  Mask l;  // an L whose centroid (about (6, 6)) falls in the notch, outside the mask
  l.label = "7";
  l.pixels = cv::Mat1b::zeros(20, 20);
  l.pixels(cv::Rect(0, 0, 4, 20)).setTo(255);
  l.pixels(cv::Rect(0, 16, 20, 4)).setTo(255);
  Mask box;
  box.label = "9";
  box.pixels = cv::Mat1b::zeros(20, 20);
  box.pixels(cv::Rect(10, 2, 5, 5)).setTo(255);  // centroid (12, 4)
  ref.views = {{"v0", {l, box}}};
  const PromptSet set = prompts_from_masks(ref, "v0", PromptKind::Point);
  REQUIRE(set.prompts.size() == 2);
  CHECK(set.prompts[0].name == "7");
  CHECK(l.pixels(set.prompts[0].positive[0]) == 255);
  CHECK(set.prompts[1].positive[0] == cv::Point(12, 4));
  CHECK(prompts_from_masks(ref, "v0", PromptKind::Mask).prompts[1].mask.data == box.pixels.data);
  CHECK_THROWS_AS(prompts_from_masks(ref, "v1", PromptKind::Point), InputError);
  CHECK_THROWS_AS(prompts_from_masks(ref, "v0", PromptKind::Scribble), InputError);
}

TEST_CASE("one prompt by name: the one click of a user, or an error naming the prompts there are") {
  PromptSet set;
  for (const char* name : {"table", "lamp"}) {
    Prompt p;
    p.name = name;
    p.positive = {cv::Point(int(set.prompts.size()), 3)};
    set.prompts.push_back(p);
  }
  set.vote_balance = {{0.5f}, {-0.5f}};
  const PromptSet lamp = prompt_named(set, "lamp");
  REQUIRE(lamp.prompts.size() == 1);
  CHECK(lamp.prompts[0].positive[0] == cv::Point(1, 3));
  CHECK(lamp.vote_balance.empty());
  CHECK_THROWS_WITH(prompt_named(set, "bed"),
                    Catch::Contains("'bed'") && Catch::Contains("'table', 'lamp'"));
  CHECK_THROWS_AS(prompt_named(PromptSet{}, "bed"), InputError);
}

TEST_CASE("prompts in a free camera select as prompts in the capture's view do") {
  const GaussianModel model = feature_scene();
  const Capture capture = one_view();
  PromptSegmenter seg(model, capture, {});
  const Camera& cam = capture.views[0].camera;
  const Pose& pose = capture.views[0].pose;
  // The features come from a sparse render at the clicked pixels, yet score as the full map's.
  PromptSelection s = seg.select_in_camera(point({{17, 24}}), cam, pose, 0.75);
  CHECK(selected(s) == std::vector<int>{0, 2});
  CHECK(s.score[2] == Approx(0.9 / std::sqrt(0.82)).margin(1e-4));
  // tau is the caller's (the viewer's slider): 0.4 admits Gaussian 3, a negative click drops it.
  CHECK(selected(seg.select_in_camera(point({{17, 24}}), cam, pose, 0.4)) ==
        std::vector<int>{0, 2, 3});
  CHECK(selected(seg.select_in_camera(point({{17, 24}}, {{47, 24}}), cam, pose, 0.4)) ==
        std::vector<int>{0, 2});
  Prompt scribble = point({{14, 24}, {20, 24}}, {{44, 24}, {50, 24}});
  scribble.kind = PromptKind::Scribble;
  CHECK(selected(seg.select_in_camera(scribble, cam, pose, 0.4)) == std::vector<int>{0, 2});
  // A camera moved 0.5 to the right sees the right blob (e2) at the centre column 32; Gaussian 3
  // (cos 0.866 with e2) comes with it.
  Pose moved = pose;
  moved.t.x() -= 0.5;
  CHECK(selected(seg.select_in_camera(point({{32, 24}}), cam, moved, 0.75)) ==
        std::vector<int>{1, 3});
  Prompt mask = point({});
  mask.kind = PromptKind::Mask;
  mask.mask = cv::Mat1b(48, 64, uint8_t(255));
  CHECK_THROWS_AS(seg.select_in_camera(mask, cam, pose, 0.75), InputError);
  CHECK_THROWS_AS(seg.select_in_camera(point({{64, 1}}), cam, pose, 0.75), InputError);
}

TEST_CASE("view_mask: a click's answer per pixel of a view, by the rule that selected Gaussians") {
  const GaussianModel model = feature_scene();
  const Capture capture = one_view();
  PromptSegmenter seg(model, capture, PromptOptions{});
  const PromptSelection s = seg.select(point({{17, 24}}));
  const cv::Mat1b m = seg.view_mask(s, 0);
  REQUIRE(m.size() == cv::Size(64, 48));
  CHECK(m(24, 17) == 255);  // the left blob's centre
  CHECK(m(24, 47) == 0);    // the right blob's (cos 0)
  CHECK(m(0, 0) == 0);      // no Gaussian: no feature
  // With a negative click on the right blob, the left blob's pixels still pass.
  CHECK(seg.view_mask(seg.select(point({{17, 24}}, {{47, 24}})), 0)(24, 17) == 255);
}
