// Path params: a relative value written in a graph file is relative to that file's folder (like
// `extends:`); values from the command line stay relative to the current directory.
#include <fstream>

#include <catch2/catch.hpp>

#include "graph/loader.hpp"
#include "param/param_table.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
namespace fs = std::filesystem;

namespace {

struct ReadOptions {
  std::string file;
  std::string name;
};

const ParamTable<ReadOptions>& read_table() {
  static const ParamTable<ReadOptions> table =
      ParamTable<ReadOptions>()
          .add("file", &ReadOptions::file, "what to read")
          .path()
          .add("name", &ReadOptions::name, "a label, not a path");
  return table;
}

class PathCatalog : public NodeCatalog {
 public:
  PathCatalog() { spec_ = NodeSpec{"io.read", "reads a file", {}, {}, read_table().specs()}; }
  const NodeSpec* find(const std::string& type) const override {
    return type == spec_.type ? &spec_ : nullptr;
  }
  std::vector<std::string> types() const override { return {spec_.type}; }

 private:
  NodeSpec spec_;
};

void write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

std::string param(const LoadResult& r, const std::string& node, const std::string& name) {
  for (const auto& d : r.diagnostics) INFO(d.str());
  REQUIRE(r.ok());
  return std::get<std::string>(r.graph->find(node)->params.at(name));
}

}  // namespace

TEST_CASE("ParamTable marks path params, only a string can be one") {
  const auto specs = read_table().specs();
  CHECK(specs[0].path);
  CHECK_FALSE(specs[1].path);
  struct Bad {
    int n = 0;
  };
  CHECK_THROWS_AS(ParamTable<Bad>().add("n", &Bad::n, "a count").path(), std::logic_error);
}

TEST_CASE("a relative path param is relative to the graph file that writes it") {
  const fs::path root = fs::absolute(test::scratch_dir("path_params"));
  write(root / "a/base.yaml", R"(graph: base
params: {data: "data/scene"}
nodes:
  r: {type: io.read, params: {file: "sub/f.txt", name: "sub/f.txt"}}
  s: {type: io.read, params: {file: "${data}"}}
  t: {type: io.read, params: {file: "${data}/images"}}
  u: {type: io.read, params: {file: "embedded:or?seed=3"}}
  v: {type: io.read, params: {file: "/abs/f.txt"}}
)");
  write(root / "b/c/derived.yaml", R"(extends: ../../a/base.yaml
nodes:
  s: {params: {file: "../mine.txt"}}
)");
  const PathCatalog catalog;

  const LoadResult base = load_graph(root / "a/base.yaml", catalog);
  CHECK(param(base, "r", "file") == (root / "a/sub/f.txt").string());
  CHECK(param(base, "r", "name") == "sub/f.txt");  // not a path param
  // ${data} is a graph param written in a/base.yaml: relative to a/, alone or leading a text.
  CHECK(param(base, "s", "file") == (root / "a/data/scene").string());
  CHECK(param(base, "t", "file") == (root / "a/data/scene/images").string());
  CHECK(param(base, "u", "file") == "embedded:or?seed=3");  // a scheme is not a path
  CHECK(param(base, "v", "file") == "/abs/f.txt");

  // A value the derived file writes is relative to the derived file; inherited ones are not.
  const LoadResult derived = load_graph(root / "b/c/derived.yaml", catalog);
  CHECK(param(derived, "s", "file") == (root / "b/mine.txt").string());
  CHECK(param(derived, "r", "file") == (root / "a/sub/f.txt").string());

  // The command line (--set, --input and other vars) stays relative to the current directory.
  LoadOptions cli;
  cli.sets = {"r.file=mine.txt", "params.data=cli/scene"};
  const LoadResult set = load_graph(root / "a/base.yaml", catalog, cli);
  CHECK(param(set, "r", "file") == "mine.txt");
  CHECK(param(set, "s", "file") == "cli/scene");
  CHECK(param(set, "t", "file") == "cli/scene/images");
  LoadOptions var;
  var.vars = {{"data", "input/scene"}};
  const LoadResult with_var = load_graph(root / "a/base.yaml", catalog, var);
  CHECK(param(with_var, "s", "file") == "input/scene");

  // Text read without a folder keeps its values as written.
  const LoadResult text = load_graph_text(
      "graph: t\nnodes:\n  r: {type: io.read, params: {file: x.txt}}\n", "<inline>", catalog);
  CHECK(param(text, "r", "file") == "x.txt");
}
