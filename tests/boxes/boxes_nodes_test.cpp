// boxes.cluster and boxes.prompt as graph nodes (thin adapters over cluster_boxes and
// load_vocabulary), run through the inline-graph harness.
#include <fstream>

#include "graph/loader.hpp"
#include "nodes/boxes/register.hpp"
#include "nodes/scene/boxes.hpp"
#include "nodes/scene/context_prompt.hpp"
#include "runtime/executor.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

// A source node that emits three rounds of one box plus a one-round hallucination.
Registry registry_with_source() {
  Registry reg;
  register_boxes_nodes(reg);
  reg.add(NodeSpec{"test.boxes", "fixed candidate boxes", {}, {{"boxes", "BoxSet", ""}}, {}},
          [](NodeContext& ctx) {
            BoxSet set;
            ViewBoxes view{"cam0", 3, {}};
            for (int r = 0; r < 3; ++r) {
              Box b;
              b.x2 = 10.f + r;
              b.y2 = 10.f;
              b.label = "monitor";
              b.round = r;
              view.boxes.push_back(b);
            }
            Box ghost;
            ghost.x1 = 50, ghost.y1 = 50, ghost.x2 = 60, ghost.y2 = 60;
            ghost.label = "c-arm";
            view.boxes.push_back(ghost);
            set.views.push_back(view);
            ctx.output("boxes", std::move(set));
          });
  return reg;
}

}  // namespace

TEST_CASE("boxes.cluster node: params reach the algorithm") {
  const Registry reg = registry_with_source();
  const std::string yaml =
      "graph: t\n"
      "nodes:\n"
      "  src: {type: test.boxes}\n"
      "  cluster: {type: boxes.cluster, in: {boxes: src.boxes}, params: {min_support: \"${s}\"}}\n";
  for (const auto& [support, expected] : std::vector<std::pair<int, size_t>>{{2, 1}, {1, 2}}) {
    const RunResult r =
        run_graph_text(yaml, reg, {}, LoadOptions{{{"s", std::to_string(support)}}, {}});
    REQUIRE(r.ok());
    const auto out = r.values.at("cluster.clusters").get<BoxSet>();
    CHECK(out->views.at(0).boxes.size() == expected);
  }
}

TEST_CASE("boxes.prompt node: loads the vocabulary, a bad file is bad input") {
  Registry reg;
  register_boxes_nodes(reg);
  const std::string good = std::string(GSLIFT_SOURCE_DIR) + "/graphs/vocabulary/or.yaml";
  const RunResult r = run_graph_text(
      "graph: t\nnodes:\n  p: {type: boxes.prompt, params: {vocabulary: \"" + good + "\"}}\n", reg);
  REQUIRE(r.ok());
  CHECK(r.values.at("p.prompt").get<Vocabulary>()->entities.size() == 12);

  const RunResult bad = run_graph_text(
      "graph: t\nnodes:\n  p: {type: boxes.prompt, params: {vocabulary: /nonexistent.yaml}}\n",
      reg);
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error->kind == RunError::Kind::BadInput);
  CHECK(bad.error->message.find("/nonexistent.yaml") != std::string::npos);
}

TEST_CASE("boxes.prompt: a relative vocabulary in a graph file is relative to that file") {
  namespace fs = std::filesystem;
  const fs::path dir = test::scratch_dir("prompt_relative") / "elsewhere";
  fs::create_directories(dir / "voc");
  fs::copy_file(fs::path(GSLIFT_SOURCE_DIR) / "graphs/vocabulary/or.yaml", dir / "voc/or.yaml",
                fs::copy_options::overwrite_existing);
  std::ofstream(dir / "graph.yaml")
      << "graph: t\nnodes:\n  p: {type: boxes.prompt, params: {vocabulary: voc/or.yaml}}\n";
  Registry reg;
  register_boxes_nodes(reg);
  const LoadResult loaded = load_graph(dir / "graph.yaml", reg);  // the test runs elsewhere
  for (const auto& d : loaded.diagnostics) INFO(d.str());
  REQUIRE(loaded.ok());
  RunOptions options;
  options.out_dir = test::scratch_dir("prompt_relative_run");
  const RunResult r = execute(*loaded.graph, reg, options);
  INFO((r.error ? r.error->str() : std::string()));
  REQUIRE(r.ok());
  CHECK(r.values.at("p.prompt").get<Vocabulary>()->entities.size() == 12);
}
