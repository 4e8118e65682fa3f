// Issue 15's stage-cache test on graphs/langor.yaml (small embedded OR, shortened training): a
// rerun with only lift.sigma changed loads every node before lift from the cache, reruns lift and
// what follows, and gives exactly what a run without the cache gives. The time it saves is
// measured in bench/cache (a timed unit test would decide its outcome by the machine's load).
#include <fstream>
#include <set>
#include <sstream>

#include "nodes/builtin.hpp"
#include "report/run_diff.hpp"
#include "runtime/executor.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
namespace fs = std::filesystem;

namespace {

RunResult run_langor(const Registry& registry, const std::string& sigma, StageCache* cache,
                     const fs::path& out) {
  LoadOptions load;
  load.vars["input"] = "embedded:or?seed=0&width=240&height=180";
  load.sets = {"recon.iterations=120", "instfeat.iterations=80", "lift.sigma=" + sigma};
  const LoadResult g =
      load_graph(fs::path(GSLIFT_SOURCE_DIR) / "graphs/langor.yaml", registry, load);
  REQUIRE(g.ok());
  RunOptions options;
  options.out_dir = out;
  options.cache = cache;
  RunResult run = execute(*g.graph, registry, options);
  INFO((run.error ? run.error->str() : std::string("ok")));
  REQUIRE(run.ok());
  return run;
}

std::string bytes_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST_CASE("langor: a changed lift.sigma reruns lift and what follows, nothing before it",
          "[stage_cache][langor]") {
  Registry registry;
  register_builtin_nodes(registry);
  const fs::path dir = test::scratch_dir("langor_cache");
  StageCache cache(dir / "cache", 0);
  run_langor(registry, "0.5", &cache, dir / "first");
  const RunResult changed = run_langor(registry, "0.7", &cache, dir / "changed");
  const RunResult fresh = run_langor(registry, "0.7", nullptr, dir / "fresh");

  const std::set<std::string> rerun = {"lift", "assoc", "clean", "query", "eval"};
  for (const auto& n : changed.nodes) {
    INFO(n.id);
    if (rerun.count(n.id))
      CHECK(n.cache == "miss");
    else if (n.id == "capture" || n.id == "text" || n.id == "posed")
      CHECK(n.cache == "off");  // Capture and TextEncoder have no binary form: they always run
    else
      CHECK(n.cache == "hit");
    CHECK(fresh.node(n.id)->cache == "off");
    // Records of loaded nodes are the stored ones; of rerun nodes, the same computation's. Both
    // equal the fresh run's, except the timings nodes record of themselves.
    for (const auto& [key, value] : n.records)
      if (!report::is_time_record(key)) {
        INFO(key);
        CHECK(fresh.node(n.id)->records.at(key) == value);
      }
  }
  // Every output value, compared in its binary form.
  for (const auto& [name, value] : changed.values) {
    const PortCodec* codec = registry.codec(value.type_name());
    if (!codec) continue;
    INFO(name);
    ByteWriter a, b;
    codec->write(value, a);
    codec->write(fresh.values.at(name), b);
    CHECK(a.bytes() == b.bytes());
  }
  // Every file either run wrote, byte for byte (run.json holds timings and cache states).
  size_t files = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir / "fresh")) {
    if (!e.is_regular_file() || e.path().filename() == "run.json") continue;
    const fs::path rel = fs::relative(e.path(), dir / "fresh");
    INFO(rel.string());
    REQUIRE(fs::exists(dir / "changed" / rel));
    CHECK(bytes_of(e.path()) == bytes_of(dir / "changed" / rel));
    ++files;
  }
  CHECK(files >= 10);
}
