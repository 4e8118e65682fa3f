// `extends:` chains (tests/data/graphs): params override, per-node merge, type swaps, and
// diagnostics that point at the file the value came from.
#include <catch2/catch.hpp>

#include "graph/loader.hpp"
#include "tests/graph/fake_catalog.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using gslift::test::test_data;
using gslift::test::with_code;

namespace {

const gslift::test::FakeCatalog& catalog() {
  static const gslift::test::FakeCatalog c;
  return c;
}

std::vector<std::string> ids(const Graph& g) {
  std::vector<std::string> out;
  for (const auto& n : g.nodes) out.push_back(n.id);
  return out;
}

}  // namespace

TEST_CASE("a one-level extends merges params and nodes key by key") {
  const auto r = load_graph(test_data("graphs/variants/middle.yaml"), catalog());
  for (const auto& d : r.diagnostics) INFO(d.str());
  REQUIRE(r.ok());
  const Graph& g = *r.graph;
  CHECK(g.name == "base");
  REQUIRE(g.files.size() == 2);
  CHECK(g.files[0] == test_data("graphs/base.yaml").lexically_normal().string());
  CHECK(g.files[1] == test_data("graphs/variants/middle.yaml").string());
  CHECK(std::get<double>(g.params.at("scale")) == 3.0);  // middle overrides base's 2.0
  CHECK(std::get<std::string>(g.params.at("label")) == "base");
  const GraphNode* total = g.find("total");
  REQUIRE(total);
  CHECK(total->type == "math.add");
  CHECK(std::get<int64_t>(total->params.at("count")) == 4);   // from middle
  CHECK(std::get<double>(total->params.at("scale")) == 3.0);  // base's "${scale}", middle's value
  CHECK(total->param_locs.at("count").str() ==
        test_data("graphs/variants/middle.yaml").string() + ":5:27");
  CHECK(total->param_locs.at("scale").line == 10);  // written in base.yaml
  CHECK(total->inputs.at("a").str() == "one.value");
  CHECK(ids(g) == std::vector<std::string>{"one", "two", "total", "show", "three"});
}

TEST_CASE("a two-level chain with a type swap restarts the node's params") {
  const auto r = load_graph(test_data("graphs/variants/leaf.yaml"), catalog());
  for (const auto& d : r.diagnostics) INFO(d.str());
  REQUIRE(r.ok());
  const Graph& g = *r.graph;
  CHECK(g.name == "leaf");
  CHECK(g.files.size() == 3);
  const GraphNode* total = g.find("total");
  REQUIRE(total);
  CHECK(total->type == "math.mul");
  // count and scale belonged to math.add: dropped; math.mul's default filled in.
  REQUIRE(total->params.size() == 1);
  CHECK(std::get<double>(total->params.at("factor")) == 2.0);
  CHECK(total->inputs.at("a").str() == "one.value");    // inherited from base.yaml
  CHECK(total->inputs.at("b").str() == "three.value");  // rewired by leaf.yaml
  CHECK(g.find("show")->inputs.at("value").str() == "total.product");
  // `two` now feeds nothing; `three` must run before `total`.
  CHECK(ids(g) == std::vector<std::string>{"one", "two", "three", "total", "show"});
  const auto dropped = with_code(r, "dropped-params");
  REQUIRE(dropped.size() == 1);
  CHECK(dropped[0].severity == Diagnostic::Severity::Warning);
  CHECK(dropped[0].loc.str() == test_data("graphs/variants/leaf.yaml").string() + ":5:17");
  CHECK(dropped[0].message ==
        "node 'total' changes type from math.add to math.mul; its earlier params are dropped: "
        "count, scale");
}

TEST_CASE("an error in a derived file points at the derived file's line") {
  const auto r = load_graph(test_data("graphs/variants/bad_leaf.yaml"), catalog());
  REQUIRE_FALSE(r.ok());
  const auto errors = with_code(r, "unknown-param");
  REQUIRE(errors.size() == 1);
  CHECK(errors[0].loc.str() == test_data("graphs/variants/bad_leaf.yaml").string() + ":5:14");
  CHECK(errors[0].hint == "did you mean 'scale'?");
}

TEST_CASE("a swap to a type without an inherited input drops it with a warning") {
  const std::string yaml =
      "extends: base.yaml\n"
      "nodes:\n"
      "  total: {type: src.make}\n";
  const auto r = load_graph_text(yaml + "  show: {in: {value: total.value}}\n", "swap.yaml",
                                 catalog(), {}, test_data("graphs"));
  for (const auto& d : r.diagnostics) INFO(d.str());
  REQUIRE(r.ok());
  const auto dropped = with_code(r, "dropped-inputs");
  REQUIRE(dropped.size() == 2);  // a and b of math.add
  CHECK(dropped[0].loc.line == 9);
  CHECK(dropped[0].loc.file == (test_data("graphs") / "base.yaml").lexically_normal().string());
  CHECK(r.graph->find("total")->inputs.empty());
  // show consumed total.sum; src.make has no such output, which is an error even after a swap.
  const auto r2 = load_graph_text(yaml + "  show: {in: {value: total.sum}}\n", "swap.yaml",
                                  catalog(), {}, test_data("graphs"));
  REQUIRE(with_code(r2, "unknown-output-port").size() == 1);
  CHECK(with_code(r2, "unknown-output-port")[0].loc.str() == "swap.yaml:4:22");
}

TEST_CASE("extends errors: a missing base and a cycle of files") {
  const auto missing = load_graph(test_data("graphs/variants/missing_base.yaml"), catalog());
  const auto unreadable = with_code(missing, "unreadable-file");
  REQUIRE(unreadable.size() == 1);
  CHECK(unreadable[0].loc.str() ==
        test_data("graphs/variants/missing_base.yaml").string() + ":1:10");
  const auto cycle =
      with_code(load_graph(test_data("graphs/variants/cycle_a.yaml"), catalog()), "extends-cycle");
  REQUIRE(cycle.size() == 1);
  CHECK(cycle[0].message.find("cycle_a.yaml -> ") != std::string::npos);
  CHECK(cycle[0].loc.line == 1);
  const auto absent = load_graph(test_data("graphs/absent.yaml"), catalog());
  REQUIRE(with_code(absent, "unreadable-file").size() == 1);
  CHECK(with_code(absent, "unreadable-file")[0].loc.line == 0);
}

TEST_CASE("a node declared null removes the base's node, one the base lacks is an error") {
  // A production graph drops the evaluated graph's leaf this way.
  const auto r = load_graph_text("extends: base.yaml\nnodes:\n  show: null\n", "prod.yaml",
                                 catalog(), {}, test_data("graphs"));
  for (const auto& d : r.diagnostics) INFO(d.str());
  REQUIRE(r.ok());
  CHECK(ids(*r.graph) == std::vector<std::string>{"one", "two", "total"});
  // `~` says the same; a consumer left without its producer is the usual unknown-node error.
  const auto consumer = load_graph_text("extends: base.yaml\nnodes:\n  total: ~\n", "prod.yaml",
                                        catalog(), {}, test_data("graphs"));
  REQUIRE(with_code(consumer, "unknown-node").size() == 1);
  const auto typo = load_graph_text("extends: base.yaml\nnodes:\n  shw: null\n", "prod.yaml",
                                    catalog(), {}, test_data("graphs"));
  const auto nothing = with_code(typo, "nothing-to-remove");
  REQUIRE(nothing.size() == 1);
  CHECK(nothing[0].loc.str() == "prod.yaml:3:3");
  CHECK(nothing[0].hint.find("show") != std::string::npos);
  // In a file that extends nothing there is nothing to remove.
  const auto alone = load_graph_text("graph: g\nnodes:\n  one: {type: src.make}\n  two: null\n",
                                     "alone.yaml", catalog());
  REQUIRE(with_code(alone, "nothing-to-remove").size() == 1);
}

TEST_CASE(
    "an input declared null unwires the base's input, one the base does not wire is an error") {
  // Production SAGA replaces its ground-truth reference masks by a prompt file this way.
  const auto r = load_graph_text(
      "extends: base.yaml\nnodes:\n  total: {type: math.mul, in: {b: null}}\n"
      "  show: {in: {value: total.product}}\n",
      "prod.yaml", catalog(), {}, test_data("graphs"));
  std::string diagnostics;
  for (const auto& d : r.diagnostics) diagnostics += d.str() + "\n";
  INFO(diagnostics);
  REQUIRE(r.ok());
  const auto& inputs = r.graph->find("total")->inputs;
  CHECK(inputs.size() == 1);
  CHECK(inputs.count("a") == 1);
  const auto typo = load_graph_text("extends: base.yaml\nnodes:\n  total: {in: {c: null}}\n",
                                    "prod.yaml", catalog(), {}, test_data("graphs"));
  const auto nothing = with_code(typo, "nothing-to-remove");
  REQUIRE(nothing.size() == 1);
  CHECK(nothing[0].loc.str() == "prod.yaml:3:16");
  CHECK(nothing[0].message.find("input 'c' of node 'total'") != std::string::npos);
}
