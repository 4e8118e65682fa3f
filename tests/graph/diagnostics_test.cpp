// One case per diagnostic code: the code, the file:line:column it points at and the hint.
#include <random>
#include <set>

#include <catch2/catch.hpp>

#include "graph/diagnostics.hpp"
#include "graph/loader.hpp"
#include "tests/graph/fake_catalog.hpp"

using namespace gslift;
using gslift::test::load_test_yaml;
using gslift::test::position;
using gslift::test::with_code;

namespace {

// The only diagnostic with `code`, which must exist.
Diagnostic only(const LoadResult& result, const std::string& code) {
  const auto found = with_code(result, code);
  INFO(code);
  for (const auto& d : result.diagnostics) INFO(d.str());
  REQUIRE(found.size() == 1);
  return found.front();
}

}  // namespace

TEST_CASE("Diagnostic::str formats file:line:col, severity, code, message and hint") {
  Diagnostic d{Diagnostic::Severity::Error, SourceLoc{"g.yaml", 3, 14}, "unknown-type",
               "node 'x' has unknown type 'math.ad'", "did you mean 'math.add'?"};
  CHECK(d.str() ==
        "g.yaml:3:14: error[unknown-type]: node 'x' has unknown type 'math.ad' (did you mean "
        "'math.add'?)");
  d.severity = Diagnostic::Severity::Warning;
  d.hint.clear();
  d.loc = SourceLoc{"--set x.type=math.ad", 0, 0};
  CHECK(d.str() ==
        "--set x.type=math.ad: warning[unknown-type]: node 'x' has unknown type 'math.ad'");
}

TEST_CASE("yaml-syntax: the parser's position and message") {
  const auto r = load_test_yaml("graph: t\n  bad: indent\nnodes: {}\n");
  REQUIRE_FALSE(r.ok());
  REQUIRE(r.diagnostics.size() == 1);
  CHECK(r.diagnostics[0].str() == "test.yaml:2:6: error[yaml-syntax]: illegal map value");
  // An unclosed flow map is reported where the parser gives up.
  const auto unclosed = load_test_yaml("graph: t\nnodes:\n  a: {type: src.make\n  b: [1, 2\n");
  REQUIRE(unclosed.diagnostics.size() == 1);
  CHECK(unclosed.diagnostics[0].loc.str() == "test.yaml:4:4");
}

TEST_CASE("duplicate-key: node ids and keys inside a node") {
  const std::string yaml =
      "graph: t\n"
      "nodes:\n"
      "  a: {type: src.make}\n"
      "  a: {type: src.make}\n"
      "  b: {type: sink.number, in: {value: a.value}, in: {value: a.value}}\n";
  const auto r = load_test_yaml(yaml);
  REQUIRE_FALSE(r.ok());
  const auto dups = with_code(r, "duplicate-key");
  REQUIRE(dups.size() == 2);
  CHECK(dups[0].loc.str() == "test.yaml:4:3");
  CHECK(dups[0].message == "duplicate node id 'a'");
  CHECK(dups[0].hint == "first defined at line 3");
  CHECK(dups[1].loc.str() == "test.yaml:5:48");
  CHECK(dups[1].loc.str() == position(yaml, "in:", 2));
  CHECK(dups[1].message == "duplicate key 'in'");
}

TEST_CASE("unknown-key: top level and inside a node, with the nearest key") {
  const std::string yaml =
      "graph: t\n"
      "node: {}\n"
      "nodes:\n"
      "  a: {type: src.make, parmas: {value: 2}}\n";
  const auto r = load_test_yaml(yaml);
  const auto unknown = with_code(r, "unknown-key");
  REQUIRE(unknown.size() == 2);
  CHECK(unknown[0].loc.str() == "test.yaml:2:1");
  CHECK(unknown[0].hint == "did you mean 'nodes'?");
  CHECK(unknown[1].loc.str() == position(yaml, "parmas"));
  CHECK(unknown[1].hint == "did you mean 'params'?");
  CHECK(unknown[1].message == "unknown key 'parmas' in node 'a'");
}

TEST_CASE("unknown-key: a param or input written outside params:/in: says so") {
  const std::string yaml =
      "nodes:\n"
      "  one: {type: src.make, value: 2}\n"
      "  show: {type: sink.number, value: one.value}\n";
  const auto unknown = with_code(load_test_yaml(yaml), "unknown-key");
  REQUIRE(unknown.size() == 2);
  CHECK(unknown[0].loc.str() == "test.yaml:2:25");
  CHECK(unknown[0].hint == "'value' is a param of src.make: write it under params:");
  CHECK(unknown[1].loc.str() == position(yaml, "value", 2));
  CHECK(unknown[1].hint == "'value' is an input of sink.number: write it under in:");
}

TEST_CASE("unknown-type: points at the type, suggests the nearest registered type") {
  const std::string yaml = "nodes:\n  a: {type: src.mkae}\n";
  const auto d = only(load_test_yaml(yaml), "unknown-type");
  CHECK(d.loc.str() == "test.yaml:2:13");
  CHECK(d.hint == "did you mean 'src.make'?");
  CHECK(only(load_test_yaml("nodes:\n  a: {type: splat.reconstruct}\n"), "unknown-type").hint ==
        "`gslift nodes` lists the types");
  CHECK(d.str() ==
        "test.yaml:2:13: error[unknown-type]: node 'a' has unknown type 'src.mkae' (did you "
        "mean 'src.make'?)");
}

TEST_CASE("missing-type: a node no file gives a type") {
  const auto d = only(load_test_yaml("nodes:\n  a: {params: {value: 1}}\n"), "missing-type");
  CHECK(d.loc.str() == "test.yaml:2:3");
}

TEST_CASE("unknown-param: points at the key, suggests the nearest param") {
  const std::string yaml = "nodes:\n  a: {type: src.make, params: {valeu: 2}}\n";
  const auto d = only(load_test_yaml(yaml), "unknown-param");
  CHECK(d.loc.str() == position(yaml, "valeu"));
  CHECK(d.hint == "did you mean 'value'?");
}

TEST_CASE("param-type: string for float, float for int, scalar for list") {
  const std::string yaml =
      "nodes:\n"
      "  one: {type: src.make}\n"
      "  two: {type: src.make}\n"
      "  sum:\n"
      "    type: math.add\n"
      "    in: {a: one.value, b: two.value}\n"
      "    params: {scale: \"high\", count: 2.5, weights: 0.5, ks: [1, 2.5], verbose: yes}\n";
  const auto r = load_test_yaml(yaml);
  const auto errors = with_code(r, "param-type");
  REQUIRE(errors.size() == 5);
  // Params are checked in name order: count, ks, scale, verbose, weights.
  CHECK(errors[0].loc.str() == position(yaml, "2.5"));
  CHECK(errors[0].message == "param 'count' of node 'sum' (math.add): expected int, got float");
  CHECK(errors[1].message ==
        "param 'ks' of node 'sum' (math.add): expected list<int>, got list<float>");
  CHECK(errors[2].loc.str() == "test.yaml:7:21");
  CHECK(errors[2].loc.str() == position(yaml, "\"high\""));
  CHECK(errors[2].message == "param 'scale' of node 'sum' (math.add): expected float, got string");
  CHECK(errors[3].message == "param 'verbose' of node 'sum' (math.add): expected bool, got string");
  CHECK(errors[4].message ==
        "param 'weights' of node 'sum' (math.add): expected list<float>, got float");
}

TEST_CASE("param-range: bounds, list elements and string choices") {
  const std::string yaml =
      "nodes:\n"
      "  one: {type: src.make, params: {value: 100.5}}\n"
      "  sum: {type: math.add, in: {a: one.value, b: one.value},\n"
      "        params: {mode: slow, weights: [0.5, -1]}}\n";
  const auto r = load_test_yaml(yaml);
  const auto errors = with_code(r, "param-range");
  REQUIRE(errors.size() == 3);
  CHECK(errors[0].loc.str() == "test.yaml:2:41");
  CHECK(errors[0].message ==
        "param 'value' of node 'one' (src.make): value 100.5 is above the "
        "maximum 100.0");
  CHECK(errors[1].loc.str() == position(yaml, "slow"));
  CHECK(errors[1].message ==
        "param 'mode' of node 'sum' (math.add): value \"slow\" is not one of: fast, exact");
  CHECK(errors[2].loc.str() == position(yaml, "[0.5"));
  CHECK(errors[2].message ==
        "param 'weights' of node 'sum' (math.add): value -1.0 is below the minimum 0.0");
}

TEST_CASE("missing-param: a required param without default") {
  const std::string yaml =
      "nodes:\n  t: {type: src.text}\n  p: {type: sink.print, in: {text: t.text}}\n";
  const auto d = only(load_test_yaml(yaml), "missing-param");
  CHECK(d.loc.str() == "test.yaml:2:3");
  CHECK(d.message == "node 't' (src.text) needs param 'text' (string): the text");
}

TEST_CASE("missing-input: required ports must be wired, optional ones need not") {
  const std::string yaml =
      "nodes:\n"
      "  one: {type: src.make}\n"
      "  sum: {type: math.add, in: {a: one.value}}\n"
      "  mul: {type: math.mul, in: {a: sum.sum}}\n";
  const auto d = only(load_test_yaml(yaml), "missing-input");
  CHECK(d.loc.str() == "test.yaml:3:3");
  CHECK(d.message == "node 'sum' (math.add) needs input 'b' (Number)");
  CHECK(d.hint == "outputs of type Number: one.value, mul.product");
}

TEST_CASE("missing-input: an optional input wired without the input it needs beside it") {
  const std::string alone =
      "nodes:\n"
      "  one: {type: src.make}\n"
      "  aff: {type: math.affine, in: {value: one.value, offset: one.value}}\n";
  const auto d = only(load_test_yaml(alone), "missing-input");
  CHECK(d.loc.str() == position(alone, "offset"));
  CHECK(d.message ==
        "node 'aff' (math.affine) input 'offset' needs input 'scale' (Number) wired "
        "with it");
  CHECK(d.hint == "outputs of type Number: one.value");
  // Both wired, or neither: valid.
  CHECK(load_test_yaml("nodes:\n  one: {type: src.make}\n"
                       "  aff: {type: math.affine, in: {value: one.value, offset: one.value, "
                       "scale: one.value}}\n")
            .ok());
  CHECK(load_test_yaml("nodes:\n  one: {type: src.make}\n"
                       "  aff: {type: math.affine, in: {value: one.value}}\n")
            .ok());
  // The partner alone is not refused: only the port that names it needs it.
  CHECK(load_test_yaml("nodes:\n  one: {type: src.make}\n"
                       "  aff: {type: math.affine, in: {value: one.value, scale: one.value}}\n")
            .ok());
}

TEST_CASE("unknown-input-port: points at the port, suggests the nearest") {
  const std::string yaml =
      "nodes:\n"
      "  one: {type: src.make}\n"
      "  mul: {type: math.mul, in: {a: one.value, bb: one.value}}\n";
  const auto d = only(load_test_yaml(yaml), "unknown-input-port");
  CHECK(d.loc.str() == position(yaml, "bb"));
  CHECK(d.hint == "did you mean 'b'?");
}

TEST_CASE("bad-reference: an input that is not node.port") {
  const std::string yaml =
      "nodes:\n"
      "  one: {type: src.make}\n"
      "  mul: {type: math.mul, in: {a: one}}\n"
      "  mul2: {type: math.mul, in: {a: one.value.x}}\n"
      "  mul3: {type: math.mul, in: {a: [one, value]}}\n";
  const auto errors = with_code(load_test_yaml(yaml), "bad-reference");
  REQUIRE(errors.size() == 3);
  CHECK(errors[0].loc.str() == "test.yaml:3:33");
  CHECK(errors[0].message == "input 'a' of node 'mul' must be of the form node.port, got 'one'");
  CHECK(errors[1].loc.str() == position(yaml, "one.value.x"));
  CHECK(errors[2].loc.str() == position(yaml, "[one"));
}

TEST_CASE("unknown-node: a reference to a missing node, nearest id as hint") {
  const std::string yaml =
      "nodes:\n"
      "  one: {type: src.make}\n"
      "  mul: {type: math.mul, in: {a: onee.value}}\n";
  const auto d = only(load_test_yaml(yaml), "unknown-node");
  CHECK(d.loc.str() == "test.yaml:3:33");
  CHECK(d.hint == "did you mean 'one'?");
}

TEST_CASE("unknown-output-port: nearest output, or the list of outputs when none is near") {
  const std::string yaml =
      "nodes:\n"
      "  one: {type: src.make}\n"
      "  sum: {type: math.add, in: {a: one.valeu, b: one.zzzzzzzz}}\n";
  const auto errors = with_code(load_test_yaml(yaml), "unknown-output-port");
  REQUIRE(errors.size() == 2);
  CHECK(errors[0].loc.str() == position(yaml, "one.valeu"));
  CHECK(errors[0].hint == "did you mean 'value'?");
  CHECK(errors[1].loc.str() == position(yaml, "one.zzzzzzzz"));
  CHECK(errors[1].hint == "expected one of: value");
}

TEST_CASE("type-mismatch: names both port types") {
  const std::string yaml =
      "nodes:\n"
      "  one: {type: src.make}\n"
      "  p: {type: sink.print, in: {text: one.value}}\n";
  const auto d = only(load_test_yaml(yaml), "type-mismatch");
  CHECK(d.loc.str() == "test.yaml:3:36");
  CHECK(d.message ==
        "input 'text' of node 'p' (sink.print) takes String, but 'one.value' of node 'one' "
        "(src.make) gives Number");
  CHECK(d.hint.empty());  // no String output in the graph
  const std::string with_text = yaml + "  t: {type: src.text, params: {text: hi}}\n";
  CHECK(only(load_test_yaml(with_text), "type-mismatch").hint == "outputs of type String: t.text");
}

TEST_CASE("cycle: each cycle named once, in data-flow order from its first declared node") {
  const std::string yaml =
      "nodes:\n"
      "  one: {type: src.make}\n"
      "  a: {type: math.add, in: {a: one.value, b: c.sum}}\n"
      "  b: {type: math.add, in: {a: a.sum, b: one.value}}\n"
      "  c: {type: math.add, in: {a: b.sum, b: b.sum}}\n"
      "  after: {type: sink.number, in: {value: c.carry}}\n"
      "  self: {type: math.mul, in: {a: self.product}}\n";
  const auto errors = with_code(load_test_yaml(yaml), "cycle");
  REQUIRE(errors.size() == 2);
  CHECK(errors[0].message == "the graph has a cycle: a -> b -> c -> a");
  CHECK(errors[0].loc.str() == "test.yaml:3:3");
  CHECK(errors[1].message == "the graph has a cycle: self -> self");
  CHECK(errors[1].loc.str() == "test.yaml:7:3");
}

TEST_CASE("bad-id: node ids are [a-z][a-z0-9_]*, 'params' is reserved") {
  const std::string yaml =
      "nodes:\n"
      "  One: {type: src.make}\n"
      "  params: {type: src.make}\n"
      "  ok_1: {type: src.make}\n";
  const auto errors = with_code(load_test_yaml(yaml), "bad-id");
  REQUIRE(errors.size() == 2);
  CHECK(errors[0].loc.str() == "test.yaml:2:3");
  CHECK(errors[1].loc.str() == "test.yaml:3:3");
}

TEST_CASE("schema: wrong kinds of YAML values and an empty graph") {
  const std::string yaml =
      "graph: [t]\n"
      "nodes:\n"
      "  a: [src.make]\n"
      "  b: {type: src.make, in: one.value}\n";
  const auto errors = with_code(load_test_yaml(yaml), "schema");
  REQUIRE(errors.size() == 3);
  CHECK(errors[0].loc.str() == "test.yaml:1:8");
  CHECK(errors[1].loc.str() == "test.yaml:3:6");
  CHECK(errors[2].loc.str() == position(yaml, "one.value"));
  const auto empty = load_test_yaml("graph: t\n");
  REQUIRE(with_code(empty, "schema").size() == 1);
  CHECK(with_code(empty, "schema")[0].message == "the graph has no nodes");
  CHECK(with_code(load_test_yaml("- a\n- b\n"), "schema").size() == 1);
}

TEST_CASE("unused-output: warned for partly consumed nodes only, without blocking") {
  const std::string yaml =
      "nodes:\n"
      "  one: {type: src.make}\n"
      "  sum: {type: math.add, in: {a: one.value, b: one.value}}\n"
      "  show: {type: sink.number, in: {value: sum.sum}}\n"
      "  lonely: {type: src.make}\n";
  const auto r = load_test_yaml(yaml);
  REQUIRE(r.ok());
  const auto d = only(r, "unused-output");
  CHECK(d.severity == Diagnostic::Severity::Warning);
  CHECK(d.loc.str() == "test.yaml:3:3");
  CHECK(d.message == "node 'sum' (math.add) has outputs no node consumes: carry");
  CHECK(r.diagnostics.size() == 1);
}

TEST_CASE("all errors are reported at once, in reading order") {
  const std::string yaml =
      "graph: t\n"
      "nodes:\n"
      "  one: {type: src.mkae}\n"
      "  sum: {type: math.add, in: {a: one.value, b: too.value}, params: {scal: 2}}\n"
      "  p: {type: sink.print, in: {text: sum.sum}}\n";
  const auto r = load_test_yaml(yaml);
  REQUIRE_FALSE(r.ok());
  std::vector<std::string> codes;
  for (const auto& d : r.diagnostics) codes.push_back(d.code);
  // The warning is still given: sum.carry is consumed by no node.
  CHECK(codes == std::vector<std::string>{"unknown-type", "unknown-param", "unknown-node",
                                          "type-mismatch", "unused-output"});
}

TEST_CASE("an alias of an enclosing value is reported, not followed forever") {
  const std::string yaml = "nodes:\n  a: {type: src.make, params: {value: &x [1, *x]}}\n";
  const auto r = load_test_yaml(yaml);
  REQUIRE_FALSE(r.ok());
  const auto d = only(r, "schema");
  CHECK(d.loc.str() == position(yaml, "&x"));
  CHECK(with_code(r, "param-type").size() == 1);
}

TEST_CASE("mangled graph files give diagnostics with documented codes, never an exception") {
  const std::string valid =
      "graph: t\n"
      "params: {n: 2, name: \"x\"}\n"
      "nodes:\n"
      "  one: {type: src.make, params: {value: 1.5}}\n"
      "  sum: {type: math.add, in: {a: one.value, b: one.value},\n"
      "        params: {count: \"${n}\", tags: [\"${name}/a\", b], weights: [1, 2]}}\n"
      "  show:\n"
      "    type: sink.number\n"
      "    in: {value: sum.sum}\n";
  REQUIRE(load_test_yaml(valid).ok());
  const std::set<std::string> documented{"yaml-syntax",
                                         "duplicate-key",
                                         "unknown-key",
                                         "unknown-type",
                                         "missing-type",
                                         "unknown-param",
                                         "param-type",
                                         "param-range",
                                         "missing-param",
                                         "missing-input",
                                         "unknown-input-port",
                                         "bad-reference",
                                         "unknown-node",
                                         "unknown-output-port",
                                         "type-mismatch",
                                         "cycle",
                                         "unknown-var",
                                         "bad-substitution",
                                         "bad-set",
                                         "bad-id",
                                         "schema",
                                         "unreadable-file",
                                         "extends-cycle",
                                         "unused-output",
                                         "dropped-params",
                                         "dropped-inputs"};
  const std::string alphabet = ":{}[],-\"'$ \n#&*.!|>?%@`0a";
  std::mt19937 rng(7);
  int failed = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::string yaml = valid;
    const int edits = 1 + static_cast<int>(rng() % 3);
    for (int e = 0; e < edits; ++e) {
      const size_t at = rng() % yaml.size();
      switch (rng() % 3) {
        case 0:
          yaml.erase(at, 1);
          break;
        case 1:
          yaml.insert(yaml.begin() + at, alphabet[rng() % alphabet.size()]);
          break;
        default:
          yaml[at] = alphabet[rng() % alphabet.size()];
      }
    }
    LoadResult r;
    REQUIRE_NOTHROW(r = load_test_yaml(yaml));
    if (!r.ok()) {
      ++failed;
      CHECK_FALSE(r.diagnostics.empty());
    }
    for (const auto& d : r.diagnostics) {
      INFO(yaml << "\n" << d.str());
      CHECK(documented.count(d.code) == 1);
      CHECK(!d.message.empty());
    }
  }
  CHECK(failed > 100);  // the mutations do break most files
}

// Issue 33: a diagnostic quoted the graph file and --set whole and raw, so a 1 MB type gave 1 MB of
// stderr and an escape sequence in a value reached the terminal.
TEST_CASE("diagnostics quote input capped, with control characters escaped") {
  const std::string huge = "\x1b]0;title\x07" + std::string(1000000, 'x');
  const auto bounded = [&](const Diagnostic& d) {
    INFO(d.str().substr(0, 300));
    CHECK(d.str().size() < 1000);
    CHECK(d.str().find_first_of("\x1b\x07") == std::string::npos);
    CHECK(d.str().find("\\x1B]0;title\\x07xxx") != std::string::npos);
    CHECK(d.str().find("... (1000010 bytes)") != std::string::npos);
  };
  bounded(only(load_test_yaml("nodes:\n  a: {type: \"" + huge + "\"}\n"), "unknown-type"));
  bounded(only(load_test_yaml("nodes:\n  a: {type: sink.number, in: {value: \"" + huge + "\"}}\n"),
               "bad-reference"));
  LoadOptions set;
  set.sets = {"a.value=1", huge + ".value=2"};
  bounded(only(load_test_yaml("nodes:\n  a: {type: src.make}\n", set), "bad-set"));
  // The node type stays named after a long node id (YAML keys stop at 1024 bytes).
  const auto both =
      only(load_test_yaml("nodes:\n  " + std::string(1000, 'a') + ": {type: \"\x1b[2J\"}\n"),
           "unknown-type");
  CHECK(both.message.find("has unknown type '\\x1B[2J'") != std::string::npos);
}

TEST_CASE("Diagnostics bounds a message whatever its site quoted") {
  Diagnostics d;
  d.error(SourceLoc{"g.yaml", 1, 1}, "x", std::string(1000000, 'm') + "\x1b[2J",
          "hint \x9b" + std::string(1000000, 'h'));
  const Diagnostic& only_one = d.list().at(0);
  CHECK(only_one.message.size() < 1000);
  CHECK(only_one.message.find("... (1000004 bytes)") != std::string::npos);
  CHECK(only_one.hint.size() < 1000);
  CHECK(only_one.hint.rfind("hint \\x9B", 0) == 0);
}
