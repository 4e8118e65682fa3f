// The pieces the report's charts are laid out with: layers, crossings, concurrency, ticks, the
// Pareto front; hand-computed cases.
#include <catch2/catch.hpp>

#include "report/charts.hpp"
#include "report/layered_layout.hpp"
#include "report/pareto.hpp"
#include "report/timeline.hpp"

using namespace gslift::report;

TEST_CASE("layered layout: longest-path layers, no overlap, skip edges get a lane", "[report]") {
  // 0 -> 1 -> 2, and 0 -> 2 skips layer 1.
  const LayeredLayout l = layered_layout({100, 60, 80}, {{0, 1}, {1, 2}, {0, 2}}, 20);
  CHECK(l.layer == std::vector<int>{0, 1, 2});
  REQUIRE(l.route.size() == 3);
  CHECK(l.route[0].empty());
  CHECK(l.route[1].empty());
  REQUIRE(l.route[2].size() == 1);  // one lane, on layer 1, beside node 1 and not through it
  const double lane = l.route[2][0];
  CHECK((lane <= l.x[1] - 10 + 1e-9 || lane >= l.x[1] + 60 + 10 - 1e-9));
  REQUIRE(l.order.size() == 3);
  CHECK(l.order[1].size() == 2);  // node 1 and the dummy of edge 2
  CHECK(l.crossings == 0);
  CHECK(l.width >= 100);
}

TEST_CASE("layered layout: barycenter ordering removes an avoidable crossing", "[report]") {
  // Layer 0: a0, a1; layer 1: b0 (fed by a1), b1 (fed by a0). In index order the two edges
  // cross; swapping b0 and b1 does not.
  const LayeredLayout l = layered_layout({50, 50, 50, 50}, {{0, 3}, {1, 2}}, 10);
  CHECK(l.layer == std::vector<int>{0, 0, 1, 1});
  CHECK(l.crossings == 0);
  CHECK((l.x[0] < l.x[1]) == (l.x[3] < l.x[2]));
  // Items of one layer never overlap: at least the gap apart.
  CHECK(std::abs(l.x[0] - l.x[1]) >= 50 + 10 - 1e-9);
  CHECK(std::abs(l.x[2] - l.x[3]) >= 50 + 10 - 1e-9);
}

TEST_CASE("layered layout: a cycle does not hang and lands below the rest", "[report]") {
  const LayeredLayout l = layered_layout({10, 10, 10}, {{1, 2}, {2, 1}}, 5);
  CHECK(l.layer[0] == 0);
  CHECK(l.layer[1] == 1);
  CHECK(l.layer[2] == 1);
}

TEST_CASE("running_count steps and the most nodes that ran at once", "[report]") {
  // [0,2) and [1,3) overlap over [1,2); [3,4) starts as [1,3) ends: not concurrent; [5,5) is
  // empty.
  const std::vector<Interval> runs = {{0, 2}, {1, 3}, {3, 4}, {5, 5}};
  const auto steps = running_count(runs);
  const std::vector<std::pair<double, int>> expected = {{0, 1}, {1, 2}, {2, 1}, {3, 1}, {4, 0}};
  CHECK(steps == expected);
  CHECK(max_running(runs) == 2);
  CHECK(max_running({}) == 0);
}

TEST_CASE("pareto_front keeps the points no other beats on time and metric", "[report]") {
  //              0       1       2       3       4       5 (NaN: left out)
  const std::vector<ChartPoint> p = {{1, 5}, {2, 4}, {2, 6}, {3, 7}, {4, 6}, {0.5, NAN}};
  CHECK(pareto_front(p, false) == std::vector<size_t>{0, 2, 3});
  // Lower is better: (1,5) then (2,4); nothing later is lower.
  CHECK(pareto_front(p, true) == std::vector<size_t>{0, 1});
  CHECK(pareto_front({}, false).empty());
}

namespace {
void check_ticks(const std::vector<double>& got, const std::vector<double>& expected) {
  REQUIRE(got.size() == expected.size());
  for (size_t i = 0; i < got.size(); ++i) CHECK(got[i] == Approx(expected[i]).margin(1e-12));
}
}  // namespace

TEST_CASE("nice_ticks picks round steps", "[report]") {
  check_ticks(nice_ticks(0, 96.08, 8), {0, 20, 40, 60, 80});  // step 96.08 / 8 = 12 -> 20
  check_ticks(nice_ticks(0.5, 1.02, 5), {0.6, 0.8, 1.0});     // 0.104 -> 0.2
  check_ticks(nice_ticks(-7, 7, 7), {-6, -4, -2, 0, 2, 4, 6});
  check_ticks(nice_ticks(3, 3, 5), {3});
}
