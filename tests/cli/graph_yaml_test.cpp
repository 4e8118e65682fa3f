#include "cli/graph_yaml.hpp"
#include "graph/loader.hpp"
#include "runtime/executor.hpp"
#include "tests/runtime/debug_nodes.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

namespace {
const char* kYaml = R"(graph: sums
params: {v: 2.5}
nodes:
  a: {type: debug.constant, params: {value: "${v}"}}
  b: {type: debug.random}
  s: {type: debug.add, in: {a: a.out, b: b.out}}
  f: {type: debug.fail, in: {in: s.out}, params: {kind: input}}
)";
}  // namespace

TEST_CASE("the printed resolved graph loads back to the same graph", "[graph_yaml]") {
  const Registry reg = test::debug_registry();
  const LoadResult first = load_graph_text(kYaml, "sums.yaml", reg);
  REQUIRE(first.ok());
  const std::string printed = graph_yaml(*first.graph);
  CHECK(printed.find("  f:\n    type: debug.fail\n    in: {in: s.out}\n"
                     "    params: {kind: \"input\", message: \"boom\"}\n") != std::string::npos);
  const LoadResult again = load_graph_text(printed, "printed.yaml", reg);
  REQUIRE(again.ok());
  const Graph& g1 = *first.graph;
  const Graph& g2 = *again.graph;
  CHECK(g2.name == "sums");
  CHECK(g2.params == g1.params);
  REQUIRE(g2.nodes.size() == g1.nodes.size());
  for (size_t i = 0; i < g1.nodes.size(); ++i) {
    CHECK(g2.nodes[i].id == g1.nodes[i].id);
    CHECK(g2.nodes[i].type == g1.nodes[i].type);
    CHECK(g2.nodes[i].params == g1.nodes[i].params);
    CHECK(g2.nodes[i].inputs.size() == g1.nodes[i].inputs.size());
  }
}

TEST_CASE("run_graph_text runs an inline graph and exposes its outputs", "[graph_yaml]") {
  const Registry reg = test::debug_registry();
  const RunResult r = run_graph_text(kYaml, reg, {}, LoadOptions{{{"v", "4"}}, {}});
  CHECK(r.status == RunStatus::Failed);
  REQUIRE(r.error);
  CHECK(r.error->node == "f");
  CHECK(r.error->loc.str() == "<inline>:7:3");
  CHECK(r.values.at("a.out").get<test::Number>()->value == 4.0);
  CHECK(r.values.at("s.out").get<test::Number>()->value ==
        4.0 + r.values.at("b.out").get<test::Number>()->value);

  CHECK_THROWS_WITH(run_graph_text("nodes:\n  x: {type: debug.nope}\n", reg),
                    Catch::Contains("invalid inline graph:") && Catch::Contains("<inline>:2:") &&
                        Catch::Contains("debug.nope"));
}
