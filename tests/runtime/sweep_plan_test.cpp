// The sweep's plan from its command line (runtime/sweep.hpp): --grid values as --set takes them,
// and the grids that cannot be a sweep refused before anything is planned (issue 33).
#include "runtime/sweep.hpp"

#include <cmath>

#include "base/statistics.hpp"

#include "tests/test_support.hpp"

using namespace gslift;
using Catch::Matchers::Contains;
using Values = std::vector<std::string>;

// The name does not start with "--": ctest passes it to Catch, which would read an option.
TEST_CASE("a --grid value splits at commas outside the quotes and brackets that close", "[sweep]") {
  CHECK(parse_grid("lift.x=[1,2],[3,4]").values == Values{"[1,2]", "[3,4]"});
  CHECK(parse_grid("n.s='a,b',c").values == Values{"'a,b'", "c"});
  // A quote or bracket that never closes is a character of its value, as in --set.
  CHECK(parse_grid("capture.path=a'b").values == Values{"a'b"});
  CHECK(parse_grid("n.p=a'b,c\"d,[e,f]g]").values == Values{"a'b", "c\"d", "[e,f]g]"});
  CHECK(parse_grid("n.p=x[1,2").values == Values{"x[1", "2"});
  CHECK(parse_grid("n.p=[a,'b]").values == Values{"[a,'b]"});
  CHECK(parse_grid("n.p=],x").values == Values{"]", "x"});
  CHECK_THROWS_WITH(parse_grid("n.p=a,,b"), Contains("an empty value"));
  CHECK_THROWS_WITH(parse_grid("n.p=1,1"), Contains("value '1' is listed twice"));
}

TEST_CASE("a param on two --grid axes and a grid over the run limit are refused", "[sweep]") {
  const GridAxis a{"a.value", {"1", "2"}}, b{"b.value", {"3"}};
  CHECK(sweep_points({a, b}, {0, 1}).size() == 4);
  CHECK_THROWS_WITH(sweep_points({a, b, GridAxis{"a.value", {"5"}}}, {0}),
                    Contains("--grid a.value is given twice"));
  // 10^6 grid points: refused before planning (they took 5.5 GB, then exit 70).
  GridAxis thousand{"c.value", {}};
  for (int i = 0; i < 1000; ++i) thousand.values.push_back(std::to_string(i));
  GridAxis other = thousand;
  other.param = "d.value";
  CHECK_THROWS_WITH(sweep_points({thousand, other}, {0}), Contains("more than 10000 runs"));
  // Saturating: four such axes would overflow a 64-bit product.
  std::vector<GridAxis> axes;
  for (const char* p : {"e.v", "f.v", "g.v", "h.v", "i.v", "j.v", "k.v"}) {
    axes.push_back(thousand);
    axes.back().param = p;
  }
  CHECK_THROWS_WITH(sweep_points(axes, {0}), Contains("more than 10000 runs"));
  CHECK(sweep_points({thousand}, std::vector<uint64_t>(10, 0)).size() == 10000);
}

TEST_CASE("a capture set multiplies the plan: each combination on every capture and seed",
          "[sweep]") {
  const GridAxis a{"a.value", {"1", "2"}};
  const auto points = sweep_points({a}, {0, 1}, {"room_a", "room_b", "room_c"});
  REQUIRE(points.size() == 12);
  CHECK(points[0].input == "room_a");
  CHECK(points[1].input == "room_a");  // seeds vary fastest
  CHECK(points[1].seed == 1);
  CHECK(points[2].input == "room_b");
  CHECK(points[6].params.at("a.value") == "2");
  CHECK(sweep_points({a}, {0}).front().input.empty());
  CHECK_THROWS_WITH(sweep_points({a}, std::vector<uint64_t>(5001, 0), {"x", "y"}),
                    Contains("more than 10000 runs"));
}

TEST_CASE("a grid's stage swap is set before its params, whatever their names", "[sweep]") {
  // Params sort by name: "prompt.tau" before "prompt.type". Set in that order the swap would
  // drop the tau just set, and every cell would run the new stage at its default tau.
  SweepPoint point;
  point.params = {{"prompt.tau", "0.9"},
                  {"prompt.type", "prompt.flashsplat"},
                  {"a.b", "1"},
                  {"recon.type", "splat.reconstruct"},
                  {"subtype", "x"}};
  CHECK(sweep_point_sets(point) == Values{"prompt.type=prompt.flashsplat",
                                          "recon.type=splat.reconstruct", "a.b=1", "prompt.tau=0.9",
                                          "subtype=x"});
}

TEST_CASE("paired differences against the first combination, with a 95% t interval by hand",
          "[sweep]") {
  const GridAxis a{"a.value", {"1", "2"}};
  // Variant 2 minus variant 1 per room: +2, +4, +9 (mean 5, sd sqrt(13)), the third room's
  // variant-2 run failed in a fourth room, which is left out of the pairs.
  std::vector<SweepRun> runs;
  const auto add = [&](const std::string& value, const std::string& room, double m, bool ok) {
    SweepRun r;
    r.point = {{{"a.value", value}}, 0, room};
    r.status = ok ? "ok" : "failed";
    if (ok) r.metrics["eval.mIoU"] = m;
    runs.push_back(r);
  };
  add("1", "r1", 50, true), add("1", "r2", 60, true), add("1", "r3", 70, true);
  add("1", "r4", 80, true);
  add("2", "r1", 52, true), add("2", "r2", 64, true), add("2", "r3", 79, true);
  add("2", "r4", 0, false);
  const auto sweep = sweep_json("g.yaml", {a}, {0}, runs, {"r1", "r2", "r3", "r4"});
  const auto& m = sweep["summary"][1]["paired"]["metrics"]["eval.mIoU"];
  CHECK(m["n"] == 3);
  CHECK(m["mean"].get<double>() == Approx(5.0));
  const double half = 4.303 * std::sqrt(13.0) / std::sqrt(3.0);  // t_{0.975,2} = 4.303
  CHECK(m["low"].get<double>() == Approx(5.0 - half));
  CHECK(m["high"].get<double>() == Approx(5.0 + half));
  const std::string table = sweep_table({a}, sweep, {"eval.mIoU"});
  CHECK_THAT(table, Contains("paired, a.value=2 minus 1: eval.mIoU +5 [-3.96, +14] (n 3)"));
}

TEST_CASE("Student's t quantile: the table and the expansion beyond it", "[sweep]") {
  CHECK(student_t_975(1) == Approx(12.706));
  CHECK(student_t_975(4) == Approx(2.776));
  CHECK(student_t_975(19) == Approx(2.093));
  // Values from R's qt(0.975, df): the expansion past the table.
  CHECK(student_t_975(31) == Approx(2.0395).epsilon(1e-4));
  CHECK(student_t_975(40) == Approx(2.0211).epsilon(1e-4));
  CHECK(student_t_975(100) == Approx(1.9840).epsilon(1e-4));
  CHECK(std::isnan(student_t_975(0)));
}
