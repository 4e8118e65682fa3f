// ${} substitution (LoadOptions::vars and graph params), --set overrides and topological order.
#include <catch2/catch.hpp>

#include "graph/loader.hpp"
#include "tests/graph/fake_catalog.hpp"

using namespace gslift;
using gslift::test::load_test_yaml;
using gslift::test::position;
using gslift::test::with_code;

namespace {

const std::string kSumGraph =
    "graph: sums\n"
    "params: {n: 3, w: [0.5, 1.5], flag: true, name: abc, scale: 2}\n"
    "nodes:\n"
    "  one: {type: src.make}\n"
    "  total:\n"
    "    type: math.add\n"
    "    in: {a: one.value, b: one.value}\n"
    "    params: {count: \"${n}\", weights: \"${w}\", verbose: \"${flag}\", scale: \"${scale}\",\n"
    "             tags: [\"${name}/x\", \"$${literal}\", \"${n}-${name}\"], mode: \"${m}\"}\n"
    "  show: {type: sink.number, in: {value: total.sum}}\n";

template <class T>
T param(const LoadResult& r, const std::string& node, const std::string& name) {
  REQUIRE(r.ok());
  return std::get<T>(r.graph->find(node)->params.at(name));
}

}  // namespace

TEST_CASE("substitution keeps the source's type for whole values and inserts text otherwise") {
  LoadOptions options;
  options.vars = {{"m", "exact"}};
  const auto r = load_test_yaml(kSumGraph, options);
  for (const auto& d : r.diagnostics) INFO(d.str());
  REQUIRE(r.ok());
  CHECK(param<int64_t>(r, "total", "count") == 3);
  CHECK(param<std::vector<double>>(r, "total", "weights") == std::vector<double>{0.5, 1.5});
  CHECK(param<bool>(r, "total", "verbose") == true);
  CHECK(param<double>(r, "total", "scale") == 2.0);  // int param source, float declared
  CHECK(param<std::vector<std::string>>(r, "total", "tags") ==
        std::vector<std::string>{"abc/x", "${literal}", "3-abc"});
  CHECK(param<std::string>(r, "total", "mode") == "exact");
  // Graph::params holds the graph's params, typed from their YAML, plus the vars.
  CHECK(std::get<int64_t>(r.graph->params.at("n")) == 3);
  CHECK(std::get<std::string>(r.graph->params.at("m")) == "exact");
}

TEST_CASE("vars win over graph params and are typed by the declared param") {
  LoadOptions options;
  options.vars = {{"m", "fast"}, {"n", "7"}, {"scale", "0.25"}};
  const auto r = load_test_yaml(kSumGraph, options);
  CHECK(param<int64_t>(r, "total", "count") == 7);
  CHECK(param<double>(r, "total", "scale") == 0.25);
  CHECK(param<std::vector<std::string>>(r, "total", "tags")[2] == "7-abc");
  CHECK(std::get<int64_t>(r.graph->params.at("n")) == 7);
}

TEST_CASE("unknown-var and bad-substitution point at the value") {
  const auto r = load_test_yaml(kSumGraph);  // ${m} is defined nowhere
  const auto unknown = with_code(r, "unknown-var");
  REQUIRE(unknown.size() == 1);
  CHECK(unknown[0].loc.str() == position(kSumGraph, "\"${m}\""));
  CHECK(unknown[0].message == "undefined variable '${m}'");
  CHECK(unknown[0].hint == "did you mean 'n'?");
  const std::string yaml =
      "nodes:\n"
      "  t: {type: src.text, params: {text: \"a ${oops\"}}\n"
      "  u: {type: src.text, params: {text: \"a ${nope} b\"}}\n";
  const auto r2 = load_test_yaml(yaml);
  REQUIRE(with_code(r2, "bad-substitution").size() == 1);
  CHECK(with_code(r2, "bad-substitution")[0].loc.str() == position(yaml, "\"a ${oops"));
  REQUIRE(with_code(r2, "unknown-var").size() == 1);
  CHECK(with_code(r2, "unknown-var")[0].loc.str() == position(yaml, "\"a ${nope"));
}

TEST_CASE("set overrides: typed node params, lists and graph params") {
  LoadOptions options;
  options.vars = {{"m", "fast"}};
  options.sets = {
      "total.scale=0.7",     "total.count=5",    "total.weights=[1, 2]", "total.tags=[a, \"b c\"]",
      "total.verbose=false", "total.mode=exact", "params.n=9",           "one.value = -3"};
  const auto r = load_test_yaml(kSumGraph, options);
  for (const auto& d : r.diagnostics) INFO(d.str());
  CHECK(param<double>(r, "total", "scale") == 0.7);
  CHECK(param<int64_t>(r, "total", "count") == 5);
  CHECK(param<std::vector<double>>(r, "total", "weights") == std::vector<double>{1.0, 2.0});
  CHECK(param<std::vector<std::string>>(r, "total", "tags") ==
        std::vector<std::string>{"a", "b c"});
  CHECK(param<bool>(r, "total", "verbose") == false);
  CHECK(param<std::string>(r, "total", "mode") == "exact");
  CHECK(param<double>(r, "one", "value") == -3.0);
  CHECK(std::get<int64_t>(r.graph->params.at("n")) == 9);
  CHECK(r.graph->find("total")->param_locs.at("scale").str() == "--set total.scale=0.7");
}

TEST_CASE("set overrides: params.NAME feeds the substitution of NAME") {
  LoadOptions options;
  options.vars = {{"m", "fast"}};
  options.sets = {"params.n=11"};
  CHECK(param<int64_t>(load_test_yaml(kSumGraph, options), "total", "count") == 11);
}

TEST_CASE("set overrides: a NAME without a dot is the graph param NAME") {
  LoadOptions options;
  options.vars = {{"m", "fast"}};
  options.sets = {"n=12"};
  const auto r = load_test_yaml(kSumGraph, options);
  CHECK(std::get<int64_t>(r.graph->params.at("n")) == 12);
  CHECK(param<int64_t>(r, "total", "count") == 12);
  // The later of the two spellings wins, as with any repeated --set.
  options.sets = {"n=12", "params.n=13"};
  CHECK(param<int64_t>(load_test_yaml(kSumGraph, options), "total", "count") == 13);
  options.sets = {"nn=1", "=1"};
  const auto bad = with_code(load_test_yaml(kSumGraph, options), "bad-set");
  REQUIRE(bad.size() == 2);
  CHECK(bad[0].str() ==
        "--set nn=1: error[bad-set]: the graph has no param 'nn' (did you mean 'n'?)");
  CHECK(bad[1].loc.str() == "--set =1");
}

TEST_CASE("set overrides: node.type swaps a stage, params restart, later sets apply") {
  const std::string yaml =
      "nodes:\n"
      "  one: {type: src.make}\n"
      "  scaled: {type: math.add, in: {a: one.value, b: one.value}, params: {scale: 2}}\n";
  LoadOptions options;
  options.sets = {"scaled.type=math.mul", "scaled.factor=3"};
  const auto r = load_test_yaml(yaml, options);
  for (const auto& d : r.diagnostics) INFO(d.str());
  REQUIRE(r.ok());
  const GraphNode* scaled = r.graph->find("scaled");
  CHECK(scaled->type == "math.mul");
  CHECK(scaled->params.size() == 1);
  CHECK(std::get<double>(scaled->params.at("factor")) == 3.0);
  CHECK(scaled->inputs.at("b").str() == "one.value");
  const auto dropped = with_code(r, "dropped-params");
  REQUIRE(dropped.size() == 1);
  CHECK(dropped[0].loc.str() == "--set scaled.type=math.mul");
  CHECK(dropped[0].message.find("dropped: scale") != std::string::npos);
}

TEST_CASE("set overrides: errors say which --set and suggest the nearest name") {
  LoadOptions options;
  options.vars = {{"m", "fast"}};
  options.sets = {"totl.scale=1", "total.scael=1",   "params.nn=1",       "total",
                  "total.a.b=1",  "total.count=1.5", "total.scale=[1, 2", "total.type=[a]"};
  const auto r = load_test_yaml(kSumGraph, options);
  REQUIRE_FALSE(r.ok());
  const auto bad = with_code(r, "bad-set");
  REQUIRE(bad.size() == 6);
  CHECK(bad[0].str() ==
        "--set totl.scale=1: error[bad-set]: the graph has no node 'totl' (did you mean "
        "'total'?)");
  CHECK(bad[1].loc.str() == "--set params.nn=1");
  CHECK(bad[1].hint == "did you mean 'n'?");
  CHECK(bad[2].loc.str() == "--set total");
  CHECK(bad[3].loc.str() == "--set total.a.b=1");
  CHECK(bad[4].loc.str() == "--set total.scale=[1, 2");
  CHECK(bad[5].loc.str() == "--set total.type=[a]");
  const auto unknown = with_code(r, "unknown-param");
  REQUIRE(unknown.size() == 1);
  CHECK(unknown[0].loc.str() == "--set total.scael=1");
  CHECK(unknown[0].hint == "did you mean 'scale'?");
  const auto type = with_code(r, "param-type");
  REQUIRE(type.size() == 1);
  CHECK(type[0].loc.str() == "--set total.count=1.5");
  CHECK(type[0].message == "param 'count' of node 'total' (math.add): expected int, got float");
}

TEST_CASE("nodes come in Kahn order, ties broken by declaration order") {
  const std::string yaml =
      "nodes:\n"
      "  show: {type: sink.number, in: {value: mul.product}}\n"
      "  mul: {type: math.mul, in: {a: left.sum, b: right.product}}\n"
      "  right: {type: math.mul, in: {a: b}}\n"
      "  left: {type: math.add, in: {a: a.value, b: b.value}}\n"
      "  b: {type: src.make}\n"
      "  a: {type: src.make}\n"
      "  other: {type: sink.number, in: {value: a.value}}\n";
  const auto bad = load_test_yaml(yaml);
  REQUIRE(with_code(bad, "bad-reference").size() == 1);  // right.a is "b", not "b.value"
  const std::string fixed = [&] {
    std::string s = yaml;
    s.replace(s.find("{a: b}"), 6, "{a: b.value}");
    return s;
  }();
  const auto r = load_test_yaml(fixed);
  for (const auto& d : r.diagnostics) INFO(d.str());
  REQUIRE(r.ok());
  std::vector<std::string> order;
  for (const auto& n : r.graph->nodes) order.push_back(n.id);
  // Ready at first: b, a (declaration order); b frees right; a frees left and other; and so on.
  CHECK(order == std::vector<std::string>{"b", "right", "a", "left", "mul", "show", "other"});
}

TEST_CASE(
    "a preset sets the params the graph leaves unset, a param the graph sets keeps its value") {
  test::FakeCatalog catalog;
  ParamSpec recipe = string_param("recipe", "none", "a named setting", {"none", "big"});
  recipe.presets = {{"big", {{"scale", 5.0}, {"count", int64_t{4}}}}};
  catalog.add({"math.preset",
               "a node with a preset",
               {},
               {{"out", "Number", "", false}},
               {recipe, float_param("scale", 1.0, "factor", 0.0, 10.0),
                int_param("count", 1, "repetitions", 1.0)}});
  const auto load = [&](const std::string& params) {
    const LoadResult r =
        load_graph_text("graph: p\nnodes:\n  n: {type: math.preset, params: " + params + "}\n",
                        "test.yaml", catalog, LoadOptions{});
    for (const auto& d : r.diagnostics) INFO(d.str());
    REQUIRE(r.ok());
    return r.graph->find("n")->params;
  };
  // Without the preset: the defaults.
  auto p = load("{}");
  CHECK(std::get<double>(p.at("scale")) == 1.0);
  CHECK(std::get<int64_t>(p.at("count")) == 1);
  // With it: its values, recorded in the resolved graph (the stage cache and run.json see them).
  p = load("{recipe: big}");
  CHECK(std::get<double>(p.at("scale")) == 5.0);
  CHECK(std::get<int64_t>(p.at("count")) == 4);
  // A param the graph sets wins, even at its default value.
  p = load("{recipe: big, scale: 1.0}");
  CHECK(std::get<double>(p.at("scale")) == 1.0);
  CHECK(std::get<int64_t>(p.at("count")) == 4);
  // --set counts as the graph's own.
  LoadOptions set;
  set.sets = {"n.count=2"};
  const LoadResult r =
      load_graph_text("graph: p\nnodes:\n  n: {type: math.preset, params: {recipe: big}}\n",
                      "test.yaml", catalog, set);
  REQUIRE(r.ok());
  CHECK(std::get<int64_t>(r.graph->find("n")->params.at("count")) == 2);
  CHECK(std::get<double>(r.graph->find("n")->params.at("scale")) == 5.0);
}

TEST_CASE("a graph param declared null must be given with --set before anything runs") {
  const std::string yaml =
      "graph: g\n"
      "params: {n: null}\n"
      "nodes:\n"
      "  one: {type: src.make}\n"
      "  total: {type: math.add, in: {a: one.value, b: one.value}, params: {count: \"${n}\"}}\n";
  const auto unset = load_test_yaml(yaml);
  const auto errors = with_code(unset, "unset-param");
  REQUIRE(errors.size() == 1);
  CHECK(errors[0].loc.str() == position(yaml, "\"${n}\""));
  CHECK(errors[0].message.find("graph param 'n' has no value (declared null at") !=
        std::string::npos);
  CHECK(errors[0].hint == "give it with --set n=VALUE");
  LoadOptions options;
  options.sets = {"n=4"};
  CHECK(param<int64_t>(load_test_yaml(yaml, options), "total", "count") == 4);
}
