// The preflight (runtime/preflight.hpp) over node types made for the test: a capture node whose
// probe says what its capture holds, and consumers that declare needs on their capture port.
#include <atomic>
#include <fstream>

#include "base/errors.hpp"
#include "graph/loader.hpp"
#include "runtime/executor.hpp"
#include "runtime/preflight.hpp"
#include "tests/test_support.hpp"

namespace gslift {
// The test's stand-in for nodes/scene's Capture: only the port type name matters here.
struct TestCapture {};
GSLIFT_PORT_TYPE(TestCapture, "Capture");
}  // namespace gslift

using namespace gslift;
namespace fs = std::filesystem;

namespace {

struct KindOptions {
  std::string kind = "box";
};

// test.capture opens a "capture" whose inventory lacks VLM replies and held-out views, or cannot
// be opened at all when its path is "missing"; test.vlm needs replies; test.masks needs held-out
// views or automatic masks by its kind param; test.plain needs nothing. `bodies` counts node bodies
// run.
Registry preflight_registry(std::atomic<int>& bodies) {
  Registry r;
  const PortSpec capture_out{"capture", "Capture", "the capture"};
  const auto body = [&bodies](NodeContext& ctx) {
    ++bodies;
    for (const auto& out : ctx.spec().outputs)
      ctx.set_output(out.name, Value::make<TestCapture>({}));
  };
  struct PathOptions {
    std::string path;
  };
  r.add(NodeSpec{"test.capture", "opens a capture", {}, {capture_out}},
        ParamTable<PathOptions>().add("path", &PathOptions::path, "where"),
        [body](NodeContext& ctx, const PathOptions&) { body(ctx); });
  r.add_capture_probe("test.capture", [](const std::map<std::string, ParamValue>& params) {
    if (std::get<std::string>(params.at("path")) == "missing")
      throw InputError("missing: no such capture folder");
    CaptureInventory inv;
    inv[CaptureItem::VlmReplies] = {false, "/c/vlm/<view>/round_0.txt", "written by a VLM"};
    inv[CaptureItem::HeldOutViews] = {false, "a held-out view", "holdout_every"};
    inv[CaptureItem::SamAutoMasks] = {true, "/c/sam_auto/", "written by SAM"};
    return inv;
  });
  r.add(NodeSpec{"test.vlm",
                 "reads VLM replies",
                 {{"capture", "Capture", "the capture", false, {{CaptureItem::VlmReplies}}}},
                 {}},
        body);
  r.add(NodeSpec{"test.masks",
                 "reads SAM masks of its kind",
                 {{"capture",
                   "Capture",
                   "the capture",
                   false,
                   {{CaptureItem::HeldOutViews, "kind", "box"},
                    {CaptureItem::SamAutoMasks, "kind", "auto"}}}},
                 {}},
        ParamTable<KindOptions>().add("kind", &KindOptions::kind, "box or auto"),
        [body](NodeContext& ctx, const KindOptions&) { body(ctx); });
  r.add(NodeSpec{"test.plain", "needs nothing", {{"capture", "Capture", "the capture"}}, {}}, body);
  return r;
}

Graph load(const std::string& yaml, const Registry& r) {
  LoadResult loaded = load_graph_text(yaml, "preflight.yaml", r);
  REQUIRE(loaded.ok());
  return *loaded.graph;
}

const char* kGraph = R"(graph: needs
nodes:
  capture: {type: test.capture, params: {path: here}}
  vlm: {type: test.vlm, in: {capture: capture.capture}}
  box: {type: test.masks, in: {capture: capture.capture}}
  auto: {type: test.masks, in: {capture: capture.capture}, params: {kind: auto}}
  plain: {type: test.plain, in: {capture: capture.capture}}
)";

}  // namespace

TEST_CASE("preflight names every missing thing: node, where it looked, what produces it",
          "[runtime][preflight]") {
  std::atomic<int> bodies{0};
  const Registry r = preflight_registry(bodies);
  const auto problems = preflight_problems(load(kGraph, r), r);
  // vlm lacks replies, box lacks held-out views; auto's automatic masks are there, plain needs
  // none.
  REQUIRE(problems.size() == 2);
  CHECK(problems[0].find("preflight.yaml:4:3: node 'vlm' (test.vlm) needs VLM grounding replies "
                         "of capture 'capture': looked for /c/vlm/<view>/round_0.txt; written by "
                         "a VLM") == 0);
  CHECK(problems[1].find("node 'box' (test.masks) needs held-out (test) views") !=
        std::string::npos);
  CHECK(problems[1].find("looked for a held-out view; holdout_every") != std::string::npos);
}

TEST_CASE("a capture that cannot be opened is one problem naming its node",
          "[runtime][preflight]") {
  std::atomic<int> bodies{0};
  const Registry r = preflight_registry(bodies);
  const auto problems = preflight_problems(
      load("graph: g\nnodes:\n  capture: {type: test.capture, params: {path: missing}}\n"
           "  vlm: {type: test.vlm, in: {capture: capture.capture}}\n",
           r),
      r);
  REQUIRE(problems.size() == 1);
  CHECK(problems[0] ==
        "preflight.yaml:3:3: node 'capture' (test.capture) cannot open its capture: missing: no "
        "such capture folder");
}

TEST_CASE("a run that fails its preflight runs no node and fails as bad input",
          "[runtime][preflight]") {
  std::atomic<int> bodies{0};
  const Registry r = preflight_registry(bodies);
  const fs::path out = test::scratch_dir("preflight_run");
  RunOptions opt;
  opt.out_dir = out;
  const RunResult result = execute(load(kGraph, r), r, opt);
  CHECK(bodies == 0);
  CHECK(result.status == RunStatus::Failed);
  REQUIRE(result.error);
  CHECK(result.error->kind == RunError::Kind::BadInput);
  CHECK(result.error->message.find(
            "preflight: 2 problems with what the graph needs of its capture; nothing was run") !=
        std::string::npos);
  for (const auto& n : result.nodes) CHECK(n.status == NodeStatus::Pending);
  CHECK(fs::exists(out / "run.json"));

  // Without the needy nodes the same capture runs: every body once.
  const RunResult plain = execute(
      load("graph: g\nnodes:\n  capture: {type: test.capture, params: {path: here}}\n"
           "  auto: {type: test.masks, in: {capture: capture.capture}, params: {kind: auto}}\n",
           r),
      r, {});
  CHECK(plain.ok());
  CHECK(bodies == 2);
}

TEST_CASE("a folder a node's param names is looked for in the capture's folder, then as given",
          "[runtime][preflight]") {
  const fs::path root = test::scratch_dir("preflight_named_folder");
  fs::create_directories(root / "mask");
  std::ofstream(root / "mask" / "000.png") << "x";
  fs::create_directories(root / "empty");
  struct PathOptions {
    std::string path;
  };
  Registry r;
  r.add(NodeSpec{"test.capture", "opens a capture", {}, {{"capture", "Capture", "a capture"}}},
        ParamTable<PathOptions>().add("path", &PathOptions::path, "where"),
        [](NodeContext&, const PathOptions&) {});
  r.add_capture_probe("test.capture", [root](const std::map<std::string, ParamValue>&) {
    CaptureInventory inv;
    inv.root = root;
    return inv;
  });
  r.add(NodeSpec{"test.folder",
                 "reads masks from a folder",
                 {{"capture",
                   "Capture",
                   "the capture",
                   false,
                   {{CaptureItem::NamedFolder, "", "", "path", "drawn by hand"}}}},
                 {}},
        ParamTable<PathOptions>().add("path", &PathOptions::path, "the folder"),
        [](NodeContext&, const PathOptions&) {});
  const auto problems_with = [&](const std::string& folder) {
    return preflight_problems(
        load("graph: g\nnodes:\n  capture: {type: test.capture, params: {path: here}}\n"
             "  truth: {type: test.folder, in: {capture: capture.capture}, params: {path: " +
                 folder + "}}\n",
             r),
        r);
  };
  CHECK(problems_with("mask").empty());
  CHECK(problems_with((root / "mask").string()).empty());
  const auto missing = problems_with("masks");
  REQUIRE(missing.size() == 1);
  CHECK(missing[0] ==
        "preflight.yaml:4:3: node 'truth' (test.folder) needs the folder its param "
        "'path' names (masks): looked for " +
            (root / "masks" / "").string() + " and masks/ (none, or empty); drawn by hand");
  const auto empty = problems_with("empty");
  REQUIRE(empty.size() == 1);
  CHECK(empty[0].find("looked for " + (root / "empty" / "").string() + " (none, or empty)") !=
        std::string::npos);
}
