#include "nodes/boxes/cluster_boxes.hpp"

#include "tests/test_support.hpp"

using namespace gslift;

namespace {

Box box(float x1, float y1, float x2, float y2, const std::string& label, int round) {
  Box b;
  b.x1 = x1, b.y1 = y1, b.x2 = x2, b.y2 = y2;
  b.label = label;
  b.round = round;
  return b;
}

}  // namespace

TEST_CASE("IoU of hand-computed box pairs") {
  // [0,10]^2 vs [5,15]x[0,10]: intersection 50, union 150.
  CHECK(iou(box(0, 0, 10, 10, "", 0), box(5, 0, 15, 10, "", 0)) == Approx(1.0 / 3));
  // Nested: 4x4 inside 8x8: 16 / 64.
  CHECK(iou(box(0, 0, 8, 8, "", 0), box(2, 2, 6, 6, "", 0)) == Approx(0.25));
  CHECK(iou(box(0, 0, 1, 1, "", 0), box(2, 2, 3, 3, "", 0)) == 0.0);
}

TEST_CASE("LangOR Eq. 2 consensus scores on a small example") {
  // A = [0,10]^2, B = [1,0,11,10] (IoU(A,B) = 90/110), C = [0,1,10,11] (IoU(A,C) = 90/110,
  // IoU(B,C) = 81/119), D far away. t = 4, so each score is the sum of its IoUs / 3.
  const std::vector<Box> c{box(0, 0, 10, 10, "a", 0), box(1, 0, 11, 10, "a", 1),
                           box(0, 1, 10, 11, "a", 2), box(50, 50, 60, 60, "b", 0)};
  const auto s = consensus_scores(c);
  const double ab = 90.0 / 110, ac = 90.0 / 110, bc = 81.0 / 119;
  CHECK(s[0] == Approx((ab + ac) / 3));
  CHECK(s[1] == Approx((ab + bc) / 3));
  CHECK(s[2] == Approx((ac + bc) / 3));
  CHECK(s[3] == 0.0);
}

TEST_CASE("clustering picks the Eq. 2 representative, votes labels, filters by support") {
  const std::vector<Box> c{
      box(1, 0, 11, 10, "assistant surgeon", 0),
      box(0, 0, 10, 10, "Head Surgeon ", 1),
      box(0, 1, 10, 11, "head surgeon", 2),
      box(50, 50, 60, 60, "monitor", 0),  // seen in round 0 only: a hallucination
      box(100, 0, 120, 20, "lamp", 0),
      box(101, 0, 121, 20, "lamp", 0)};  // one round only
  BoxClusteringParams p;
  const auto out = cluster_boxes(c, 3, p);
  REQUIRE(out.size() == 1);
  // Box 1 ([0,10]^2) has the highest Eq. 2 score (see above): it is the representative.
  CHECK(out[0].x1 == 0);
  CHECK(out[0].y1 == 0);
  CHECK(out[0].round == 1);
  CHECK(out[0].source_index == 0);        // first box of round 1
  CHECK(out[0].label == "head surgeon");  // 2 votes to 1, case and spaces ignored
  CHECK(out[0].support == 3);

  p.min_support = 1;
  const auto all = cluster_boxes(c, 3, p);
  CHECK(all.size() == 3);  // surgeon, monitor, and the two lamp boxes (IoU 19/21) as one
  CHECK(all.back().support == 1);
}

TEST_CASE("label ties go to the higher-scoring member, single round keeps its boxes") {
  // Two boxes, two labels, one vote each: the first by score wins; equal scores -> input order.
  const std::vector<Box> c{box(0, 0, 10, 10, "nurse", 0), box(0, 0, 10, 11, "surgeon", 1)};
  const auto out = cluster_boxes(c, 2, BoxClusteringParams{});
  REQUIRE(out.size() == 1);
  CHECK(out[0].label == "nurse");
  // One round asked: min_support 2 is clamped to 1.
  const auto single = cluster_boxes({box(0, 0, 5, 5, "lamp", 0)}, 1, BoxClusteringParams{});
  REQUIRE(single.size() == 1);
  CHECK(single[0].support == 1);
}

TEST_CASE("greedy seeding does not chain two objects through an in-between box") {
  // Object 1 at x in [0,10], object 2 at [6,16] (IoU 4/16 = 0.25), 3 rounds each; round 3 adds a
  // box at [3,13] with IoU 7/13 = 0.54 > 0.5 to both. Single-linkage would chain all 7 into one
  // cluster. Eq. 2 scores: object boxes (2 + 7/13 + 3/4) / 6 = 0.548 > in-between 0.538, so an
  // object box seeds first, takes the in-between box, and object 2 stays its own cluster.
  std::vector<Box> c;
  for (int r = 0; r < 3; ++r) {
    c.push_back(box(0, 0, 10, 20, "nurse", r));
    c.push_back(box(6, 0, 16, 20, "surgeon", r));
  }
  c.push_back(box(3, 0, 13, 20, "person", 3));
  BoxClusteringParams label_blind;  // the in-between box may join whatever its label
  label_blind.any_label_iou = label_blind.iou;
  const auto out = cluster_boxes(c, 4, label_blind);
  REQUIRE(out.size() == 2);
  CHECK(out[0].label == "nurse");  // 3 votes to 1 for "person"
  CHECK(out[0].support == 4);
  CHECK(out[1].label == "surgeon");
  CHECK(out[1].support == 3);
}

TEST_CASE("an object resting on another keeps its own cluster, a mislabelled box is voted down") {
  // Table [0,100]x[0,40], patient on it [0,100]x[0,28]: IoU 28/40 = 0.7, above iou 0.5 but below
  // any_label_iou 0.8, so the two labels stay two objects. A round that calls the table
  // "patient" with a box [0,100]x[0,42] (IoU 40/42 = 0.95 with the table, 28/42 = 0.67 with the
  // patient) is one of the table's boxes with a wrong label. Eq. 2 scores: table boxes
  // (2 + 3 * 0.7 + 0.95) / 6 = 0.84, the stray one (3 * 0.95 + 3 * 0.67) / 6 = 0.81, patient
  // boxes (2 + 3 * 0.7 + 0.67) / 6 = 0.79; a table box seeds, the stray box joins it and loses
  // the vote 3 to 1.
  std::vector<Box> c;
  for (int r = 0; r < 3; ++r) {
    c.push_back(box(0, 0, 100, 40, "operating table", r));
    c.push_back(box(0, 0, 100, 28, "patient", r));
  }
  c.push_back(box(0, 0, 100, 42, "patient", 3));
  const auto out = cluster_boxes(c, 4, BoxClusteringParams{});
  REQUIRE(out.size() == 2);
  const Box& table = out[0].label == "operating table" ? out[0] : out[1];
  const Box& patient = out[0].label == "patient" ? out[0] : out[1];
  CHECK(table.label == "operating table");
  CHECK(table.support == 4);
  CHECK(table.y2 == 40);
  CHECK(patient.label == "patient");
  CHECK(patient.support == 3);
  CHECK(patient.y2 == 28);
  // Label-blind (the paper's clustering): the seed takes everything above IoU 0.5 and one label
  // wins, the other object is gone.
  BoxClusteringParams label_blind;
  label_blind.any_label_iou = label_blind.iou;
  CHECK(cluster_boxes(c, 4, label_blind).size() == 1);
  // iou 1 (the single-round ablation's "no clustering") keeps every box, whatever the labels.
  BoxClusteringParams none;
  none.iou = 1.f;
  none.min_support = 1;
  CHECK(cluster_boxes(c, 4, none).size() == c.size());
}

TEST_CASE("cluster_box_set keeps view order and names") {
  BoxSet in;
  in.views.push_back({"cam0", 2, {box(0, 0, 4, 4, "x", 0), box(0, 0, 4, 4, "x", 1)}});
  in.views.push_back({"cam1", 2, {}});
  const BoxSet out = cluster_box_set(in, BoxClusteringParams{});
  REQUIRE(out.views.size() == 2);
  CHECK(out.views[0].view == "cam0");
  CHECK(out.views[0].boxes.size() == 1);
  CHECK(out.views[1].boxes.empty());
}
