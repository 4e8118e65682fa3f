#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>

#include "runtime/executor.hpp"
#include "tests/runtime/debug_nodes.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using gslift::test::debug_node;
using gslift::test::Number;

namespace {

Graph graph_of(std::vector<GraphNode> nodes) {
  Graph g;
  g.name = "test";
  g.files = {"test.yaml"};
  g.nodes = std::move(nodes);
  return g;
}

double number(const RunResult& r, const std::string& key) {
  return r.values.at(key).get<Number>()->value;
}

}  // namespace

TEST_CASE("independent slow nodes overlap with 2 threads and not with 1", "[executor]") {
  const Registry reg = test::debug_registry();
  const Graph g = graph_of({debug_node(reg, "a", "debug.sleep", {}, {{"ms", int64_t{300}}}),
                            debug_node(reg, "b", "debug.sleep", {}, {{"ms", int64_t{300}}})});
  RunOptions opt;
  opt.threads = 2;
  const RunResult two = execute(g, reg, opt);
  REQUIRE(two.ok());
  CHECK(two.threads == 2);
  const NodeRecord& a2 = *two.node("a");
  const NodeRecord& b2 = *two.node("b");
  CHECK(a2.end_s - a2.start_s >= 0.3);
  // Each starts before the other ends.
  CHECK(b2.start_s < a2.end_s);
  CHECK(a2.start_s < b2.end_s);

  opt.threads = 1;
  const RunResult one = execute(g, reg, opt);
  REQUIRE(one.ok());
  const NodeRecord& a1 = *one.node("a");
  const NodeRecord& b1 = *one.node("b");
  CHECK((b1.start_s >= a1.end_s || a1.start_s >= b1.end_s));
  CHECK(one.total_s >= 0.6);
}

TEST_CASE("a failing node stops the run and names node, type and line", "[executor]") {
  const Registry reg = test::debug_registry();
  const Graph g = graph_of(
      {debug_node(reg, "slow", "debug.sleep", {}, {{"ms", int64_t{5000}}}, 4),
       debug_node(reg, "early", "debug.sleep", {}, {{"ms", int64_t{50}}}, 5),
       debug_node(reg, "bad", "debug.fail", {{"in", {"early", "out"}}},
                  {{"kind", std::string("input")}, {"message", std::string("no such file x.png")}},
                  6),
       debug_node(reg, "down", "debug.sleep", {{"in", {"bad", "out"}}}, {{"ms", int64_t{0}}}, 7)});
  RunOptions opt;
  opt.threads = 2;
  const RunResult r = execute(g, reg, opt);
  CHECK(r.status == RunStatus::Failed);
  REQUIRE(r.error);
  CHECK(r.error->kind == RunError::Kind::BadInput);
  CHECK(r.error->node == "bad");
  CHECK(r.error->type == "debug.fail");
  CHECK(r.error->loc.line == 6);
  CHECK(r.error->message == "no such file x.png");
  CHECK(r.error->str() == "test.yaml:6:3: node 'bad' (debug.fail) failed: no such file x.png");
  CHECK(r.node("bad")->status == NodeStatus::Failed);
  CHECK(r.node("early")->status == NodeStatus::Ok);
  // Downstream of the failure never started.
  CHECK(r.node("down")->status == NodeStatus::Pending);
  CHECK(r.node("down")->start_s == 0);
  // The 5 s sibling saw ctx.cancelled() and stopped long before its time.
  CHECK(r.node("slow")->status == NodeStatus::Cancelled);
  CHECK(r.node("slow")->end_s < 2.0);
  // execute() returned only after every running body had finished.
  CHECK(r.node("slow")->end_s <= r.total_s);
  CHECK(r.total_s < 2.0);
  // Outputs of the nodes that finished are still visible.
  CHECK(r.values.count("early.out") == 1);
  CHECK(r.values.count("slow.out") == 0);
}

TEST_CASE("any other exception is a node failure", "[executor]") {
  const Registry reg = test::debug_registry();
  const Graph g = graph_of({debug_node(reg, "x", "debug.fail", {}, {}, 2)});
  for (int threads : {1, 2}) {
    RunOptions opt;
    opt.threads = threads;
    const RunResult r = execute(g, reg, opt);
    CHECK(r.status == RunStatus::Failed);
    REQUIRE(r.error);
    CHECK(r.error->kind == RunError::Kind::NodeFailed);
    CHECK(r.error->message == "boom");
  }
}

TEST_CASE("outputs flow along edges and seeds are deterministic per node id", "[executor]") {
  const Registry reg = test::debug_registry();
  const Graph g =
      graph_of({debug_node(reg, "r1", "debug.random"), debug_node(reg, "r2", "debug.random"),
                debug_node(reg, "sum", "debug.add", {{"a", {"r1", "out"}}, {"b", {"r2", "out"}}})});
  RunOptions opt;
  opt.seed = 7;
  opt.threads = 1;
  const RunResult one = execute(g, reg, opt);
  opt.threads = 2;
  const RunResult two = execute(g, reg, opt);
  REQUIRE(one.ok());
  REQUIRE(two.ok());
  CHECK(number(one, "r1.out") == number(two, "r1.out"));
  CHECK(number(one, "r2.out") == number(two, "r2.out"));
  CHECK(number(one, "sum.out") == number(one, "r1.out") + number(one, "r2.out"));
  CHECK(number(one, "sum.out") == number(two, "sum.out"));
  // Different node ids draw different streams; the recorded seed is node_seed(7, id).
  CHECK(number(one, "r1.out") != number(one, "r2.out"));
  CHECK(std::get<std::string>(one.node("r1")->records.at("seed")) !=
        std::get<std::string>(one.node("r2")->records.at("seed")));
  CHECK(std::get<double>(one.node("r1")->records.at("draw")) == number(one, "r1.out"));
  // Another run seed, other draws.
  opt.seed = 8;
  const RunResult other = execute(g, reg, opt);
  CHECK(number(other, "r1.out") != number(one, "r1.out"));
}

TEST_CASE("a node that does not set a declared output fails the run", "[executor]") {
  const Registry reg = test::debug_registry();
  const RunResult lazy =
      execute(graph_of({debug_node(reg, "l", "debug.lazy", {}, {}, 9)}), reg, {});
  CHECK(lazy.status == RunStatus::Failed);
  REQUIRE(lazy.error);
  CHECK(lazy.error->node == "l");
  CHECK(lazy.error->message == "node 'l' (debug.lazy) did not set its output port 'out'");

  const RunResult wrong = execute(graph_of({debug_node(reg, "w", "debug.wrong")}), reg, {});
  CHECK(wrong.status == RunStatus::Failed);
  REQUIRE(wrong.error);
  CHECK(wrong.error->message ==
        "node 'w' (debug.wrong): output port 'out' is declared Number but was given Text");
}

TEST_CASE("an external cancellation interrupts the run", "[executor]") {
  const Registry reg = test::debug_registry();
  const Graph g =
      graph_of({debug_node(reg, "s", "debug.sleep", {}, {{"ms", int64_t{5000}}, {"write", true}}),
                debug_node(reg, "after", "debug.sleep", {{"in", {"s", "out"}}})});
  std::atomic<bool> flag{false};
  RunOptions opt;
  opt.cancel = &flag;
  opt.out_dir = test::scratch_dir("executor_interrupt");
  std::thread interrupter([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    flag = true;
  });
  const RunResult r = execute(g, reg, opt);
  interrupter.join();
  CHECK(r.status == RunStatus::Interrupted);
  REQUIRE(r.error);
  CHECK(r.error->kind == RunError::Kind::Cancelled);
  CHECK(r.node("s")->status == NodeStatus::Cancelled);
  CHECK(r.node("s")->end_s < 2.0);
  CHECK(r.node("after")->status == NodeStatus::Pending);
  // The cancelled node's half-written folder is gone; the run record is there.
  CHECK_FALSE(std::filesystem::exists(opt.out_dir / "s"));
  CHECK(std::filesystem::exists(opt.out_dir / "run.json"));

  // Already set before the start: nothing runs.
  const RunResult before = execute(g, reg, opt);
  CHECK(before.status == RunStatus::Interrupted);
  CHECK(before.node("s")->status == NodeStatus::Pending);
}

namespace {
struct RecordingSink : ProgressSink {
  std::mutex m;
  std::vector<std::string> events;
  int progress_calls = 0;
  void node_started(const std::string& id, const std::string& type) override {
    std::lock_guard<std::mutex> l(m);
    events.push_back("start " + id + " " + type);
  }
  void node_progress(const std::string&, double, const std::string&) override {
    std::lock_guard<std::mutex> l(m);
    ++progress_calls;
  }
  void node_finished(const std::string& id, const std::string& status, double) override {
    std::lock_guard<std::mutex> l(m);
    events.push_back("end " + id + " " + status);
  }
};
}  // namespace

TEST_CASE("the progress sink sees every node start and finish in dependency order", "[executor]") {
  const Registry reg = test::debug_registry();
  const Graph g = graph_of(
      {debug_node(reg, "c", "debug.constant", {}, {{"value", 2.5}}),
       debug_node(reg, "s", "debug.sleep", {{"in", {"c", "out"}}}, {{"ms", int64_t{20}}})});
  RecordingSink sink;
  RunOptions opt;
  opt.progress = &sink;
  const RunResult r = execute(g, reg, opt);
  REQUIRE(r.ok());
  CHECK(number(r, "s.out") == 2.5);
  CHECK(sink.events == std::vector<std::string>{"start c debug.constant", "end c ok",
                                                "start s debug.sleep", "end s ok"});
  CHECK(sink.progress_calls >= 1);
}
