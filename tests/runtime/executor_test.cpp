#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <set>
#include <string>

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

// Where node bodies meet, so that tests of concurrency wait for events instead of timing sleeps:
// a test.meet body arrives, waits until `count` bodies have arrived (at most `wait_ms`, a bound
// that only a hung scheduler reaches), and leaves; the most bodies ever inside at once is kept.
// Two bodies that both see the other arrive ran concurrently, however loaded the machine.
struct Meeting {
  std::mutex m;
  std::condition_variable cv;
  int arrived = 0, inside = 0, most_inside = 0, met = 0;
};

// A progress sink that remembers which nodes reported progress, and lets a body wait for that:
// test.after waits (at most 60 s, then throws) until node `of` has reported progress, i.e. is
// running its body.
struct Progressed : ProgressSink {
  std::mutex m;
  std::condition_variable cv;
  std::set<std::string> ids;
  void node_started(const std::string&, const std::string&) override {}
  void node_progress(const std::string& id, double, const std::string&) override {
    std::lock_guard<std::mutex> lock(m);
    ids.insert(id);
    cv.notify_all();
  }
  void node_finished(const std::string&, const std::string&, double) override {}
};

PortSpec number_out() {
  return PortSpec{"out", "Number", "0", false};
}

struct MeetOptions {
  int count = 2;
  int wait_ms = 60000;
};
struct AfterOptions {
  std::string of;
};

Registry registry_with(const std::shared_ptr<Meeting>& meeting,
                       const std::shared_ptr<Progressed>& progressed) {
  Registry r = test::debug_registry();
  r.add(NodeSpec{"test.meet", "waits for `count` bodies to be running at once", {}, {number_out()}},
        ParamTable<MeetOptions>()
            .add("count", &MeetOptions::count, "bodies to meet", 1)
            .add("wait_ms", &MeetOptions::wait_ms, "give up after", 0),
        [meeting](NodeContext& ctx, const MeetOptions& o) {
          std::unique_lock<std::mutex> lock(meeting->m);
          ++meeting->arrived;
          meeting->most_inside = std::max(meeting->most_inside, ++meeting->inside);
          meeting->cv.notify_all();
          meeting->met += meeting->cv.wait_for(lock, std::chrono::milliseconds(o.wait_ms),
                                               [&] { return meeting->arrived >= o.count; });
          --meeting->inside;
          ctx.output("out", Number{0});
        });
  r.add(NodeSpec{"test.after", "waits until node `of` has reported progress", {}, {number_out()}},
        ParamTable<AfterOptions>().add("of", &AfterOptions::of, "node id"),
        [progressed](NodeContext& ctx, const AfterOptions& o) {
          std::unique_lock<std::mutex> lock(progressed->m);
          if (!progressed->cv.wait_for(lock, std::chrono::seconds(60),
                                       [&] { return progressed->ids.count(o.of) > 0; }))
            throw std::runtime_error("node '" + o.of + "' never reported progress");
          ctx.output("out", Number{0});
        });
  return r;
}

}  // namespace

TEST_CASE("independent nodes run concurrently with 2 threads and not with 1", "[executor]") {
  // With 2 threads both bodies get in and see each other arrive; with 1 the first one waits in
  // vain (100 ms, a chance for a wrong scheduler to start the other) and they never overlap.
  for (int threads : {2, 1}) {
    auto meeting = std::make_shared<Meeting>();
    const Registry reg = registry_with(meeting, std::make_shared<Progressed>());
    const int64_t wait_ms = threads == 2 ? 60000 : 100;
    const Graph g = graph_of({debug_node(reg, "a", "test.meet", {}, {{"wait_ms", wait_ms}}),
                              debug_node(reg, "b", "test.meet", {}, {{"wait_ms", wait_ms}})});
    RunOptions opt;
    opt.threads = threads;
    const RunResult r = execute(g, reg, opt);
    REQUIRE(r.ok());
    CHECK(r.threads == threads);
    const NodeRecord& a = *r.node("a");
    const NodeRecord& b = *r.node("b");
    if (threads == 2) {
      CHECK(meeting->met == 2);
      CHECK(meeting->most_inside == 2);
      // Each started before the other ended.
      CHECK(b.start_s < a.end_s);
      CHECK(a.start_s < b.end_s);
    } else {
      CHECK(meeting->met == 1);  // the second one found the first already arrived
      CHECK(meeting->most_inside == 1);
      CHECK((b.start_s >= a.end_s || a.start_s >= b.end_s));
    }
  }
}

TEST_CASE("a failing node stops the run and names node, type and line", "[executor]") {
  // "early" waits until "slow" is running, so "slow" is always there to be cancelled; it would
  // take a minute to finish on its own.
  auto progressed = std::make_shared<Progressed>();
  const Registry reg = registry_with(std::make_shared<Meeting>(), progressed);
  const Graph g = graph_of(
      {debug_node(reg, "slow", "debug.sleep", {}, {{"ms", int64_t{60000}}}, 4),
       debug_node(reg, "early", "test.after", {}, {{"of", std::string("slow")}}, 5),
       debug_node(reg, "bad", "debug.fail", {{"in", {"early", "out"}}},
                  {{"kind", std::string("input")}, {"message", std::string("no such file x.png")}},
                  6),
       debug_node(reg, "down", "debug.sleep", {{"in", {"bad", "out"}}}, {{"ms", int64_t{0}}}, 7)});
  RunOptions opt;
  opt.threads = 2;
  opt.progress = progressed.get();
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
  // The one-minute sibling saw ctx.cancelled() and stopped before its time (it would have ended
  // "ok" otherwise).
  CHECK(r.node("slow")->status == NodeStatus::Cancelled);
  // execute() returned only after every running body had finished.
  CHECK(r.node("slow")->end_s <= r.total_s);
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
  // "s" would sleep a minute; the flag is raised (as a signal handler would) at its first progress
  // report, i.e. once it is running and has written its partial file.
  const Graph g =
      graph_of({debug_node(reg, "s", "debug.sleep", {}, {{"ms", int64_t{60000}}, {"write", true}}),
                debug_node(reg, "after", "debug.sleep", {{"in", {"s", "out"}}})});
  std::atomic<bool> flag{false};
  struct Interrupter : ProgressSink {
    std::atomic<bool>* flag;
    void node_started(const std::string&, const std::string&) override {}
    void node_progress(const std::string&, double, const std::string&) override { *flag = true; }
    void node_finished(const std::string&, const std::string&, double) override {}
  } interrupter;
  interrupter.flag = &flag;
  RunOptions opt;
  opt.cancel = &flag;
  opt.progress = &interrupter;
  opt.out_dir = test::scratch_dir("executor_interrupt");
  const RunResult r = execute(g, reg, opt);
  CHECK(r.status == RunStatus::Interrupted);
  REQUIRE(r.error);
  CHECK(r.error->kind == RunError::Kind::Cancelled);
  CHECK(r.node("s")->status == NodeStatus::Cancelled);
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
