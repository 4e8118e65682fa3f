// gslift diff over the fixture runs: tests/data/report/run_b is run with left.factor 2 -> 3,
// right retyped, a node 'extra' added that failed, and two records changed.
#include "report/run_diff.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using namespace gslift::report;

TEST_CASE("diff_runs finds params, records, graph and status changes, hand-counted", "[report]") {
  const RunRecord a = read_run_record(test::test_data("report/run"));
  const RunRecord b = read_run_record(test::test_data("report/run_b"));
  const RunDiff d = diff_runs(a, b);
  CHECK(d.differs());

  REQUIRE(d.params.size() == 1);
  CHECK(d.params[0].what == "left.factor");
  CHECK(d.params[0].a == "2");
  CHECK(d.params[0].b == "3");
  CHECK(d.params[0].numeric);
  CHECK(d.params[0].delta == 1.0);
  CHECK(d.same_params == 3);  // source.count, right.factor, join.mode

  REQUIRE(d.records.size() == 2);
  CHECK(d.records[0].what == "left.sum");
  CHECK(d.records[0].delta == 18.75 - 12.5);
  CHECK(d.records[1].what == "join.mIoU");
  CHECK(d.records[1].delta == 5.5);
  CHECK(d.same_records == 4);  // source.items, left.mode, right.sum, join.loss

  REQUIRE(d.graph.size() == 2);
  CHECK(d.graph[0].what == "right type");
  CHECK(d.graph[0].a == "debug.scale");
  CHECK(d.graph[0].b == "debug.scale2");
  CHECK(d.graph[1].what == "node extra");
  CHECK(d.graph[1].a == "(absent)");
  CHECK(d.graph[1].b == "debug.fail");

  REQUIRE(d.status.size() == 2);
  CHECK(d.status[0].what == "run status");
  CHECK(d.status[0].b == "failed");
  CHECK(d.status[1].what == "run error");

  // Time: total, memory and each node's wall time, not counted.
  REQUIRE(d.timing.size() == 2 + 4);
  CHECK(d.timing[0].what == "total_s");
  CHECK(d.timing[0].delta == Approx(0.5));

  const std::string text = diff_text(d, a, b);
  INFO(text);
  CHECK(text.find("params:\n  left.factor: 2 -> 3 (+1, +50.00%)\n") != std::string::npos);
  CHECK(text.find("  left.sum: 12.5 -> 18.75 (+6.25, +50.00%)\n") != std::string::npos);
  CHECK(text.find("  join.mIoU: 50 -> 55.5 (+5.5, +11.00%)\n") != std::string::npos);
  CHECK(text.find("graph:\n  right type: debug.scale -> debug.scale2\n  node extra: (absent) -> "
                  "debug.fail\n") != std::string::npos);
  CHECK(text.find("status:\n  run status: ok -> failed\n") != std::string::npos);
  CHECK(text.find("3 params and 4 records are the same; the runs differ") != std::string::npos);
}

TEST_CASE("a run compared with itself differs in nothing", "[report]") {
  const RunRecord a = read_run_record(test::test_data("report/run"));
  const RunDiff d = diff_runs(a, a);
  CHECK_FALSE(d.differs());
  CHECK(d.same_params == 4);
  CHECK(d.same_records == 6);
  CHECK(diff_text(d, a, a).find("no differences beyond time and memory") != std::string::npos);

  // A rerun: other wall times, memory, cache state and time records (recon.seconds) only.
  RunRecord rerun = a;
  rerun.total_s += 1;
  rerun.peak_rss_mb += 10;
  rerun.nodes[1].wall_s += 0.5;
  rerun.nodes[1].cache = "hit";
  rerun.nodes[1].records["seconds"] = 2.5;
  RunRecord first = a;
  first.nodes[1].records["seconds"] = 1.0;
  const RunDiff r = diff_runs(first, rerun);
  INFO(diff_text(r, first, rerun));
  CHECK_FALSE(r.differs());
  CHECK(r.same_records == 6);
  // total, memory, then per node its time records, wall_s and cache: source, left (3), right, join
  REQUIRE(r.timing.size() == 2 + 1 + 3 + 1 + 1);
  CHECK(r.timing[3].what == "left.seconds");
  CHECK(r.timing[3].delta == 1.5);
  CHECK(r.timing[5].what == "left cache");
}

TEST_CASE("is_time_record knows time records by name", "[report]") {
  CHECK(is_time_record("seconds"));
  CHECK(is_time_record("train_seconds"));
  CHECK(is_time_record("wall_s"));
  CHECK(is_time_record("step_ms"));
  // The unit anywhere in the name (issue 33: two identical reruns differed over this record).
  CHECK(is_time_record("select_ms_median"));
  CHECK(is_time_record("ms_per_view"));
  CHECK_FALSE(is_time_record("masks_per_view"));
  CHECK_FALSE(is_time_record("gaussians"));
  CHECK_FALSE(is_time_record("loss"));
  CHECK_FALSE(is_time_record("masks"));
}
