// fusion.multiview (paper 002 §3.2, Eq. 1) on two synthetic frames with a known projection: both
// cameras look down +z at a plane 2 m away; frame B sits 0.2 m to the right of frame A, so A's
// pixel (u, v) projects to B's pixel centre line u - 0.5, i.e. into B's pixel (u - 1, v).
#include "nodes/fusion/multiview_fusion.hpp"

#include <catch2/catch.hpp>

#include "base/errors.hpp"

#include "tests/pinhole.hpp"

using namespace gslift;

namespace {

constexpr int kW = 8, kH = 6;

// Two-class view: every pixel label 0 with (0.6, 0.4) unless set otherwise.
SemanticView two_class_view(const std::string& name) {
  SemanticView v;
  v.view = name;
  v.probabilities.assign(kW * kH * 2, 0.f);
  for (int p = 0; p < kW * kH; ++p) {
    v.probabilities[2 * p] = 0.6f;
    v.probabilities[2 * p + 1] = 0.4f;
  }
  set_argmax(v, 2, kW, kH);
  return v;
}

void set_pixel(SemanticView& v, int u, int y, float p0, float p1) {
  v.probabilities[2 * (y * kW + u)] = p0;
  v.probabilities[2 * (y * kW + u) + 1] = p1;
  v.labels(y, u) = p1 > p0 ? 1 : 0;
  v.confidence(y, u) = std::max(p0, p1);
}

struct TwoFrames {
  SemanticView a = two_class_view("a"), b = two_class_view("b");
  cv::Mat1f depth_a = cv::Mat1f(kH, kW, 2.f), depth_b = cv::Mat1f(kH, kW, 2.f);

  std::vector<FusionFrame> frames() const {
    const Camera cam = test::centred_pinhole(kW, kH, 10);
    Pose pa, pb;
    pb.t = Eigen::Vector3d(-0.2, 0, 0);  // camera B's centre at world x = 0.2
    return {{cam, pa, depth_a, &a}, {cam, pb, depth_b, &b}};
  }
};

const float* dist(const SemanticView& v, int u, int y) {
  return v.pixel(y * kW + u, 2);
}

}  // namespace

TEST_CASE("multi-view fusion: majority of the Moore neighbourhood and that neighbour's confidences",
          "[fusion]") {
  TwoFrames t;
  // A's pixel (4, 3) projects to B's (3, 3). Its neighbourhood in B: 5 pixels of label 1, 4 of
  // label 0 (the projected pixel itself among them).
  set_pixel(t.b, 2, 2, 0.3f, 0.7f);  // first label-1 pixel in raster order: its distribution votes
  set_pixel(t.b, 4, 2, 0.1f, 0.9f);
  set_pixel(t.b, 2, 3, 0.1f, 0.9f);
  set_pixel(t.b, 4, 4, 0.1f, 0.9f);
  set_pixel(t.b, 3, 4, 0.1f, 0.9f);
  const MultiviewFusionResult r = fuse_multiview(t.frames(), 0, 2, {});
  // (0.6 * 0.3, 0.4 * 0.7) = (0.18, 0.28) / 0.46.
  CHECK(dist(r.fused, 4, 3)[0] == Approx(0.18 / 0.46));
  CHECK(dist(r.fused, 4, 3)[1] == Approx(0.28 / 0.46));
  CHECK(r.fused.labels(3, 4) == 1);
  // Pixel (0, 3) projects outside B (u = -0.5): no contribution, the reference stays.
  CHECK(dist(r.fused, 0, 3)[0] == Approx(0.6));
  CHECK(r.fused.labels(3, 0) == 0);
}

TEST_CASE("multi-view fusion: a neighbour that fails the depth validation does not vote",
          "[fusion]") {
  TwoFrames t;
  for (int u : {2, 3, 4}) set_pixel(t.b, u, 2, 0.1f, 0.9f);
  set_pixel(t.b, 2, 3, 0.1f, 0.9f);
  set_pixel(t.b, 4, 3, 0.1f, 0.9f);  // 5 votes for label 1 ...
  SECTION("all valid: label 1 wins") {
    const MultiviewFusionResult r = fuse_multiview(t.frames(), 0, 2, {});
    CHECK(r.fused.labels(3, 4) == 1);
    CHECK(dist(r.fused, 4, 3)[1] == Approx(0.36 / (0.36 + 0.06)));  // (0.6*0.1, 0.4*0.9)
  }
  SECTION("two label-1 neighbours 1 m behind the plane: label 0 wins 4 to 3") {
    t.depth_b(2, 2) = 3.f;
    t.depth_b(2, 3) = 3.f;
    const MultiviewFusionResult r = fuse_multiview(t.frames(), 0, 2, {});
    CHECK(r.fused.labels(3, 4) == 0);
    // The projected pixel (label 0, (0.6, 0.4)) votes: (0.36, 0.16) / 0.52.
    CHECK(dist(r.fused, 4, 3)[0] == Approx(0.36 / 0.52));
  }
  SECTION("epsilon 0.05 m: a label-1 neighbour 4 cm off still votes, 6 cm off does not") {
    t.depth_b(2, 2) = 2.04f;
    CHECK(fuse_multiview(t.frames(), 0, 2, {}).fused.labels(3, 4) == 1);  // 5 votes to 4
    t.depth_b(2, 2) = 2.06f;
    const MultiviewFusionResult r = fuse_multiview(t.frames(), 0, 2, {});
    // 4 votes to 4: the tie in the neighbourhood goes to the projected pixel's own label 0, and
    // its distribution (0.6, 0.4) votes: (0.36, 0.16) / 0.52.
    CHECK(r.fused.labels(3, 4) == 0);
    CHECK(dist(r.fused, 4, 3)[0] == Approx(0.36 / 0.52));
  }
}

TEST_CASE("multi-view fusion: a tie keeps the reference label", "[fusion]") {
  TwoFrames t;
  for (int y = 0; y < kH; ++y)
    for (int u = 0; u < kW; ++u) set_pixel(t.b, u, y, 0.4f, 0.6f);
  const MultiviewFusionResult r = fuse_multiview(t.frames(), 0, 2, {});
  // (0.6 * 0.4, 0.4 * 0.6): equal products.
  CHECK(dist(r.fused, 4, 3)[0] == dist(r.fused, 4, 3)[1]);
  CHECK(r.fused.labels(3, 4) == 0);
  // With B as the reference the tie keeps B's label 1.
  const MultiviewFusionResult rb = fuse_multiview(t.frames(), 1, 2, {});
  CHECK(rb.fused.labels(3, 3) == 1);
}

TEST_CASE("multi-view fusion: invalid depth and bad sizes", "[fusion]") {
  TwoFrames t;
  t.depth_a(3, 4) = 0.f;  // no depth in the reference: the pixel stays as it is
  for (int y = 0; y < kH; ++y)
    for (int u = 0; u < kW; ++u) set_pixel(t.b, u, y, 0.1f, 0.9f);
  const MultiviewFusionResult r = fuse_multiview(t.frames(), 0, 2, {});
  CHECK(r.fused.labels(3, 4) == 0);
  CHECK(r.fused.labels(3, 5) == 1);
  t.depth_b = cv::Mat1f(kH, kW - 1, 2.f);
  CHECK_THROWS_AS(fuse_multiview(t.frames(), 0, 2, {}), InputError);
}
