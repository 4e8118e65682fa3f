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
}
