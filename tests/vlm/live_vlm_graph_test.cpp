// graphs/examples/langor_live_vlm.yaml is graphs/langor.yaml with its perceptor swapped for
// vlm.query: the loader (what `gslift validate` runs) accepts it against the built-in catalogue,
// and every other stage is exactly LangOR's.
#include <catch2/catch.hpp>

#include "graph/loader.hpp"
#include "nodes/builtin.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {

LoadResult load(const std::filesystem::path& file, const Registry& registry) {
  LoadOptions options;
  options.vars["input"] = "/captures/any_scene";  // validation never opens the input
  LoadResult r = load_graph(file, registry, options);
  for (const Diagnostic& d : r.diagnostics) UNSCOPED_INFO(d.str());
  return r;
}

}  // namespace

TEST_CASE("langor_live_vlm.yaml validates and differs from langor.yaml only in its perceptor") {
  Registry registry;
  register_builtin_nodes(registry);
  const std::filesystem::path graphs = std::filesystem::path(GSLIFT_SOURCE_DIR) / "graphs";
  const LoadResult live = load(graphs / "examples" / "langor_live_vlm.yaml", registry);
  const LoadResult base = load(graphs / "langor.yaml", registry);
  REQUIRE(live.ok());
  REQUIRE(base.ok());

  const GraphNode* vlm = live.graph->find("vlm");
  REQUIRE(vlm != nullptr);
  CHECK(vlm->type == "vlm.query");
  CHECK(vlm->inputs.at("capture").str() == "capture.capture");
  CHECK(vlm->inputs.at("prompt").str() == "prompt.prompt");
  CHECK(std::get<std::string>(vlm->params.at("url")) ==
        "http://127.0.0.1:8000/v1/chat/completions");
  CHECK(std::get<int64_t>(vlm->params.at("rounds")) == 5);
  REQUIRE(live.graph->find("prompt") != nullptr);
  CHECK(live.graph->find("prompt")->type == "boxes.prompt");
  // Written relative to graphs/examples/, resolved to the shipped vocabulary wherever gslift runs.
  CHECK(std::filesystem::equivalent(
      std::get<std::string>(live.graph->find("prompt")->params.at("vocabulary")),
      graphs / "vocabulary" / "or.yaml"));

  // The only other difference is the added prompt node.
  CHECK(live.graph->nodes.size() == base.graph->nodes.size() + 1);
  for (const GraphNode& b : base.graph->nodes) {
    if (b.id == "vlm") continue;
    const GraphNode* l = live.graph->find(b.id);
    REQUIRE(l != nullptr);
    INFO(b.id);
    CHECK(l->type == b.type);
    CHECK(l->params == b.params);
    REQUIRE(l->inputs.size() == b.inputs.size());
    for (const auto& [port, ref] : b.inputs) CHECK(l->inputs.at(port).str() == ref.str());
  }
}
