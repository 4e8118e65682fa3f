#include "cli/node_catalogue.hpp"
#include "tests/runtime/debug_nodes.hpp"
#include "tests/test_support.hpp"

using namespace gslift;

TEST_CASE("the catalogue lists every type, aligned, with its doc", "[catalogue]") {
  const Registry reg = test::debug_registry();
  const std::string text = catalogue_text(reg);
  // "debug.constant" is the longest type name (14 characters): docs start at column 16.
  CHECK(text.find("debug.add       a + b\n") == 0);
  CHECK(text.find("debug.constant  a constant\n") != std::string::npos);
  size_t lines = 0;
  for (char c : text) lines += c == '\n';
  CHECK(lines == reg.types().size());
}

TEST_CASE("one type's page shows ports and params with defaults, ranges and choices",
          "[catalogue]") {
  const Registry reg = test::debug_registry();
  CHECK(node_type_text(*reg.find("debug.sleep")) ==
        "debug.sleep: sleeps, polling cancellation\n"
        "inputs:\n"
        "  in: Number (optional)\n"
        "      a number\n"
        "outputs:\n"
        "  out: Number\n"
        "      a number\n"
        "params:\n"
        "  ms: int = 100 in [0, inf]\n"
        "      milliseconds\n"
        "  write: bool = false\n"
        "      write partial.txt into the node folder first\n");
  const std::string fail = node_type_text(*reg.find("debug.fail"));
  CHECK(fail.find("  kind: string = \"other\" one of {input, other}\n") != std::string::npos);
  CHECK(node_type_text(*reg.find("debug.random")).find("inputs:\n  (none)\n") != std::string::npos);
}

TEST_CASE("one type's page names the inputs an optional input is wired with", "[catalogue]") {
  const NodeSpec spec{"math.affine",
                      "a node",
                      {{"offset", "Number", "added", true, {}, {"scale", "value"}},
                       {"scale", "Number", "factor", true}},
                      {}};
  CHECK(node_type_text(spec) ==
        "math.affine: a node\n"
        "inputs:\n"
        "  offset: Number (optional, with scale and value)\n"
        "      added\n"
        "  scale: Number (optional)\n"
        "      factor\n"
        "outputs:\n  (none)\n"
        "params:\n  (none)\n");
}

TEST_CASE("one type's page names the file that registers it", "[catalogue]") {
  const Registry reg = test::debug_registry();
  // The debug nodes are registered in tests/runtime/debug_nodes.cpp: the registry keeps the
  // caller's file, relative to the repository root.
  CHECK(reg.source("debug.sleep") == "tests/runtime/debug_nodes.cpp");
  CHECK(node_type_text(*reg.find("debug.sleep"), reg.source("debug.sleep"))
            .rfind("debug.sleep: sleeps, polling cancellation\n"
                   "source: tests/runtime/debug_nodes.cpp\ninputs:\n",
                   0) == 0);
}

TEST_CASE("one type's page lists the advanced params under the others, and what presets set",
          "[catalogue]") {
  ParamSpec recipe = string_param("recipe", "none", "a named setting", {"none", "big"});
  recipe.presets = {{"big", {{"scale", 5.0}}}};
  ParamSpec scale = float_param("scale", 1.0, "factor");
  scale.advanced = true;
  const NodeSpec spec{"math.preset", "a node", {}, {}, {scale, recipe, int_param("n", 1, "count")}};
  CHECK(node_type_text(spec) ==
        "math.preset: a node\n"
        "inputs:\n  (none)\n"
        "outputs:\n  (none)\n"
        "params:\n"
        "  recipe: string = \"none\" one of {none, big}\n"
        "      a named setting\n"
        "      big sets {scale: 5.0}\n"
        "  n: int = 1\n"
        "      count\n"
        "advanced params:\n"
        "  scale: float = 1.0\n"
        "      factor\n");
}
