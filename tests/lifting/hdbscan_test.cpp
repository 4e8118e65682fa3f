// Known-answer cases for HDBSCAN small enough to follow by hand.
#include "nodes/lifting/hdbscan.hpp"

#include <fstream>
#include <sstream>

#include <tbb/global_control.h>

#include "base/random.hpp"
#include "nodes/lifting/cluster_agreement.hpp"
#include "nodes/lifting/numpy_argsort.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

PointMatrix line(const std::vector<double>& xs) {
  PointMatrix p(xs.size(), 1);
  for (size_t i = 0; i < xs.size(); ++i) p(i, 0) = xs[i];
  return p;
}

}  // namespace

TEST_CASE("HDBSCAN on a hand-computed 1-D example") {
  // min_samples 1: core distance = nearest-neighbour distance: 1, 1, 2, 1.5, 1.5. The MST is the
  // chain with mutual-reachability weights 1, 2, 7, 1.5. The root splits at distance 7 into
  // C1 = {0, 1, 3} and C2 = {10, 11.5}; point 3 leaves C1 at lambda 1/2, points 0 and 1 at 1, the
  // two points of C2 at 1/1.5. Both leaves are selected; probability = lambda / death.
  HdbscanParams params;
  params.min_cluster_size = 2;
  params.min_samples = 1;
  const HdbscanResult r = hdbscan(line({0, 1, 3, 10, 11.5}), params);
  CHECK(r.clusters == 2);
  CHECK(r.labels == std::vector<int>{0, 0, 0, 1, 1});
  CHECK(r.probabilities[0] == Approx(1.0));
  CHECK(r.probabilities[1] == Approx(1.0));
  CHECK(r.probabilities[2] == Approx(0.5));
  CHECK(r.probabilities[3] == Approx(1.0));
  CHECK(r.probabilities[4] == Approx(1.0));
}

TEST_CASE("HDBSCAN condensed tree stabilities of the 1-D example") {
  const std::vector<PrimEdge> mst =
      mutual_reachability_mst(line({0, 1, 3, 10, 11.5}), {1, 1, 2, 1.5, 1.5});
  REQUIRE(mst.size() == 4);
  CHECK(mst[0].to == 1);
  CHECK(mst[0].weight == 1.0);
  CHECK(mst[1].to == 2);
  CHECK(mst[1].weight == 2.0);
  CHECK(mst[2].to == 3);
  CHECK(mst[2].weight == 7.0);
  CHECK(mst[3].to == 4);
  CHECK(mst[3].weight == 1.5);
  const std::vector<CondensedEdge> tree = condense_tree(single_linkage(mst), 2);
  // Rows: root 5 -> clusters 6 (3 points) and 7 (2 points) at 1/7; then the points.
  REQUIRE(tree.size() == 7);
  CHECK(tree[0].parent == 5);
  CHECK(tree[0].child == 6);
  CHECK(tree[0].child_size == 3);
  CHECK(tree[0].lambda == Approx(1.0 / 7));
  CHECK(tree[1].child == 7);
  CHECK(tree[1].child_size == 2);
  int ones = 0;
  for (const auto& e : tree)
    if (e.child < 5) {
      ones += e.child_size == 1;
      CHECK(e.parent == (e.child < 3 ? 6 : 7));
      const double expected = e.child == 2 ? 0.5 : e.child < 2 ? 1.0 : 1 / 1.5;
      CHECK(e.lambda == Approx(expected));
    }
  CHECK(ones == 5);
}

TEST_CASE("HDBSCAN excess of mass keeps a long-lived parent, leaf selection its children") {
  // A = {0, 0.1} and B = {0.25, 0.35} split at distance 0.15 (lambda 6.67) after living together
  // from distance 4.65 (lambda 0.215): stability(AB) = 4 (6.67 - 0.215) = 25.8 beats
  // stability(A) + stability(B) = 2 * 2 (10 - 6.67) = 13.3. C = {5, 5.1} is far away.
  const PointMatrix p = line({0, 0.1, 0.25, 0.35, 5, 5.1});
  HdbscanParams params;
  params.min_cluster_size = 2;
  params.min_samples = 1;
  const HdbscanResult eom = hdbscan(p, params);
  CHECK(eom.labels == std::vector<int>{0, 0, 0, 0, 1, 1});
  params.selection = ClusterSelection::Leaf;
  const HdbscanResult leaf = hdbscan(p, params);
  CHECK(leaf.clusters == 3);
  CHECK(same_partition(leaf.labels, {0, 0, 1, 1, 2, 2}));
  // epsilon 0.2 > 0.15: the leaves A and B, born below it, are merged back into AB.
  params.cluster_selection_epsilon = 0.2;
  CHECK(same_partition(hdbscan(p, params).labels, {0, 0, 0, 0, 1, 1}));
}

TEST_CASE("HDBSCAN cannot-link groups make excess of mass give a joined parent up") {
  // The example above: excess of mass keeps AB (stability 25.8 > 13.3). Groups: A = 0, B = 1,
  // C = 2. A cannot-link between A and B forbids AB, so its children A and B are chosen.
  const PointMatrix p = line({0, 0.1, 0.25, 0.35, 5, 5.1});
  HdbscanParams params;
  params.min_cluster_size = 2;
  params.min_samples = 1;
  CannotLink cl;
  cl.point_groups = {0, 0, 1, 1, 2, 2};
  cl.pairs = {{0, 1}};
  const HdbscanResult split = hdbscan(p, params, cl);
  CHECK(split.clusters == 3);
  CHECK(same_partition(split.labels, {0, 0, 1, 1, 2, 2}));
  // A constraint AB satisfies anyway (A against C) changes nothing.
  cl.pairs = {{0, 2}};
  CHECK(hdbscan(p, params, cl).labels == std::vector<int>{0, 0, 0, 0, 1, 1});
  // "Holds" means more than half of a group: with group 1 = {0.25, 0.35, 5} AB holds 2 of its 3
  // points and still must split; with group 1 = {0.35, 5, 5.1} it holds 1 of 3 and may stay.
  cl.pairs = {{0, 1}};
  cl.point_groups = {0, 0, 1, 1, 1, -1};
  CHECK(hdbscan(p, params, cl).clusters == 3);
  cl.point_groups = {0, 0, -1, 1, 1, 1};
  CHECK(hdbscan(p, params, cl).labels == std::vector<int>{0, 0, 0, 0, 1, 1});
  // Bad constraints are named.
  cl.point_groups = {0, 0, 1};
  CHECK_THROWS_AS(hdbscan(p, params, cl), std::invalid_argument);
  cl.point_groups = {0, 0, 1, 1, 2, 2};
  cl.pairs = {{0, 7}};
  CHECK_THROWS_AS(hdbscan(p, params, cl), std::invalid_argument);
}

TEST_CASE("HDBSCAN separates two blobs from isolated noise (fixture)") {
  std::ifstream in(test::test_data("lifting/two_blobs_noise.csv"));
  REQUIRE(in);
  std::vector<double> coords;
  std::vector<int> expected;
  std::string line_text;
  while (std::getline(in, line_text)) {
    if (line_text.empty() || line_text[0] == '#' || line_text[0] == 'x') continue;
    std::replace(line_text.begin(), line_text.end(), ',', ' ');
    std::istringstream fields(line_text);
    double x, y;
    int label;
    fields >> x >> y >> label;
    coords.insert(coords.end(), {x, y});
    expected.push_back(label);
  }
  const PointMatrix points =
      Eigen::Map<const PointMatrix>(coords.data(), static_cast<int64_t>(expected.size()), 2);
  HdbscanParams params;
  params.min_cluster_size = 5;
  const HdbscanResult r = hdbscan(points, params);
  CHECK(r.clusters == 2);
  CHECK(same_partition(r.labels, expected));
  for (int c = 0; c < 2; ++c) {
    double best = 0;
    for (size_t i = 0; i < expected.size(); ++i) {
      if (r.labels[i] != c) continue;
      CHECK(r.probabilities[i] > 0.0);
      CHECK(r.probabilities[i] <= 1.0);
      best = std::max(best, r.probabilities[i]);
    }
    CHECK(best == 1.0);  // the points that stay longest have full membership
  }
  for (size_t i = 0; i < expected.size(); ++i)
    if (expected[i] == -1) CHECK(r.probabilities[i] == 0.0);

  // The same answer with one thread (determinism across thread counts).
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  const HdbscanResult serial = hdbscan(points, params);
  CHECK(serial.labels == r.labels);
  CHECK(serial.probabilities == r.probabilities);
}

TEST_CASE("HDBSCAN cosine metric clusters by direction, not length") {
  // Two rays (angles 0 and 90 degrees, slightly spread) with lengths 1..60: Euclidean distance
  // sees a continuum along each ray; cosine sees two tight directions.
  PointMatrix p(12, 2);
  for (int i = 0; i < 6; ++i) {
    const double len = 1 + 12.0 * i, jitter = 0.01 * (i + 1);
    p.row(i) << len, len * jitter;
    p.row(6 + i) << len * jitter, len;
  }
  HdbscanParams params;
  params.min_cluster_size = 4;  // 6 points per ray: no ray can split into two clusters
  params.min_samples = 2;
  params.metric = HdbscanMetric::Cosine;
  CHECK(same_partition(hdbscan(p, params).labels, {0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1}));
  p.row(0).setZero();
  CHECK_THROWS_AS(hdbscan(p, params), std::invalid_argument);
}

TEST_CASE("HDBSCAN rejects bad params and oversize input clearly") {
  HdbscanParams params;
  params.min_cluster_size = 1;
  CHECK_THROWS_AS(hdbscan(line({0, 1, 2}), params), std::invalid_argument);
  params.min_cluster_size = 2;
  CHECK(hdbscan(line({0}), params).labels == std::vector<int>{-1});
  PointMatrix nan = line({0, 1, 2});
  nan(1, 0) = std::nan("");
  CHECK_THROWS_AS(hdbscan(nan, params), std::invalid_argument);
  CHECK_THROWS_WITH(hdbscan(PointMatrix::Zero(kHdbscanMaxPoints + 1, 1), params),
                    Catch::Contains("exceed the limit"));
  CHECK_THROWS_AS(parse_cluster_selection("mean"), std::invalid_argument);
  CHECK(parse_hdbscan_metric("cosine") == HdbscanMetric::Cosine);
}

TEST_CASE("numpy_argsort sorts, and orders ties as NumPy's introsort does") {
  // Insertion-sort path (<= 16 elements) keeps equal keys in input order.
  CHECK(numpy_argsort({3, 1, 2, 1}) == std::vector<int64_t>{1, 3, 2, 0});
  // Longer arrays go through median-of-3 partitioning: check sortedness and permutation.
  std::vector<double> v;
  for (int i = 0; i < 1000; ++i) v.push_back((i * 7919) % 101);
  const auto order = numpy_argsort(v);
  std::vector<char> seen(v.size(), 0);
  for (size_t i = 0; i < order.size(); ++i) {
    seen[order[i]] = 1;
    if (i > 0) CHECK(v[order[i - 1]] <= v[order[i]]);
  }
  CHECK(std::count(seen.begin(), seen.end(), 1) == 1000);
}

TEST_CASE("HDBSCAN results do not depend on the thread count (parallel paths exercised)") {
  // 3000 points: several chunks in both the core-distance loop and each Prim step.
  RandomStream rng(9);
  PointMatrix p(3000, 4);
  for (int64_t i = 0; i < p.rows(); ++i)
    for (int k = 0; k < 4; ++k) p(i, k) = 5.0 * (i % 6 == k) + rng.normal();
  HdbscanParams params;
  params.min_cluster_size = 15;
  const HdbscanResult parallel = hdbscan(p, params);
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  const HdbscanResult serial = hdbscan(p, params);
  CHECK(parallel.clusters >= 2);
  CHECK(serial.labels == parallel.labels);
  CHECK(serial.probabilities == parallel.probabilities);
}

TEST_CASE("HDBSCAN allow_single_cluster: the root may be the one cluster") {
  // min_samples 1: core distances 1, 1, 1, 1, 1.5, 45.5. Nothing ever splits into two groups of
  // >= 3 points, so the only cluster is the root: none by default; with allow_single_cluster the
  // root, holding (as Python hdbscan does) the points that stay until its densest level (lambda
  // 1): 0..3, while 4.5 (leaves at lambda 2/3) and 50 (1/45.5) are noise.
  const PointMatrix p = line({0, 1, 2, 3, 4.5, 50});
  HdbscanParams params;
  params.min_cluster_size = 3;
  params.min_samples = 1;
  const HdbscanResult none = hdbscan(p, params);
  CHECK(none.clusters == 0);
  CHECK(none.labels == std::vector<int>(6, -1));
  params.allow_single_cluster = true;
  const HdbscanResult single = hdbscan(p, params);
  CHECK(single.clusters == 1);
  CHECK(single.labels == std::vector<int>{0, 0, 0, 0, -1, -1});
  CHECK(single.probabilities[0] == 1.0);
}

TEST_CASE("HDBSCAN excess of mass with cluster_selection_epsilon merges young clusters upwards") {
  // A = {0, 0.1} and B = {0.3, 0.4} split at distance 0.2 (lambda 5) from AB, born at 4.6
  // (lambda 0.217): stability(AB) = 4 (5 - 0.217) = 19.1 < stability(A) + stability(B) =
  // 2 * 2 (10 - 5) = 20, so excess of mass keeps A and B. With epsilon 0.25, A and B (born at
  // distance 0.2 < 0.25) are replaced by their ancestor AB (born at 4.6 > 0.25).
  const PointMatrix p = line({0, 0.1, 0.3, 0.4, 5, 5.1});
  HdbscanParams params;
  params.min_cluster_size = 2;
  params.min_samples = 1;
  CHECK(same_partition(hdbscan(p, params).labels, {0, 0, 1, 1, 2, 2}));
  params.cluster_selection_epsilon = 0.25;
  CHECK(same_partition(hdbscan(p, params).labels, {0, 0, 0, 0, 1, 1}));
}
