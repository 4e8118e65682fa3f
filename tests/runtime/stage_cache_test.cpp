// The stage cache (runtime/stage_cache.hpp) on small graphs of counting nodes: what a changed
// param, input file or seed reruns, what a damaged entry does, and eviction. The LangOR case (a
// changed lift.sigma reruns lift and what follows, nothing before) is tests/eval/
// langor_cache_test.cpp.
#include <sys/stat.h>

#include <atomic>
#include <fstream>

#include "runtime/executor.hpp"
#include "tests/runtime/debug_nodes.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using namespace gslift::test;
namespace fs = std::filesystem;

namespace {

// How often each counting node's body ran.
std::map<std::string, int>& runs() {
  static std::map<std::string, int> counts;
  return counts;
}

struct ScaleOptions {
  double factor = 1.0;
  std::string file;  // a path param: its content is part of the key
};

// count.source: out = value, and writes value.txt; count.scale: out = in * factor (+ the number
// of bytes of `file` when set), and writes scaled.txt; count.live: as count.source, but marked
// uncacheable (a live service).
Registry counting_registry() {
  Registry r = debug_registry();
  const PortSpec in{"in", "Number", "a number", false};
  const PortSpec out{"out", "Number", "a number", false};
  r.add(NodeSpec{"count.source", "counted constant", {}, {out}},
        ParamTable<ScaleOptions>().add("factor", &ScaleOptions::factor, "the value"),
        [](NodeContext& ctx, const ScaleOptions& o) {
          ++runs()[ctx.node().id];
          ctx.record("value", o.factor);
          if (!ctx.out_dir().empty()) std::ofstream(ctx.out_dir() / "value.txt") << o.factor;
          ctx.output("out", Number{o.factor});
        });
  r.add(NodeSpec{"count.scale", "counted product", {in}, {out}},
        ParamTable<ScaleOptions>()
            .add("factor", &ScaleOptions::factor, "factor")
            .add("file", &ScaleOptions::file, "a file whose size is added")
            .path(),
        [](NodeContext& ctx, const ScaleOptions& o) {
          ++runs()[ctx.node().id];
          double v = ctx.input<Number>("in")->value * o.factor;
          if (!o.file.empty()) v += double(fs::file_size(o.file));
          ctx.record("note", std::string("scaled"));
          if (!ctx.out_dir().empty()) std::ofstream(ctx.out_dir() / "scaled.txt") << v;
          ctx.output("out", Number{v});
        });
  NodeSpec live{"count.live", "counted, never cached", {}, {out}};
  live.cacheable = false;
  r.add(std::move(live), ParamTable<ScaleOptions>().add("factor", &ScaleOptions::factor, "value"),
        [](NodeContext& ctx, const ScaleOptions& o) {
          ++runs()[ctx.node().id];
          ctx.output("out", Number{o.factor});
        });
  return r;
}

Graph chain(const Registry& reg, double source, double scale, const std::string& file = {},
            const std::string& source_type = "count.source") {
  Graph g;
  g.name = "chain";
  g.nodes = {debug_node(reg, "src", source_type, {}, {{"factor", source}}),
             debug_node(reg, "mid", "count.scale", {{"in", {"src", "out"}}},
                        {{"factor", scale}, {"file", file}}),
             debug_node(reg, "end", "count.scale", {{"in", {"mid", "out"}}}, {{"factor", 1.0}})};
  return g;
}

RunResult run_cached(const Graph& g, const Registry& reg, StageCache& cache,
                     const fs::path& out = {}, uint64_t seed = 0) {
  RunOptions opt;
  opt.cache = &cache;
  opt.out_dir = out;
  opt.seed = seed;
  RunResult r = execute(g, reg, opt);
  INFO((r.error ? r.error->str() : std::string("ok")));
  REQUIRE(r.ok());
  return r;
}

double value(const RunResult& r, const std::string& node) {
  return r.values.at(node + ".out").get<Number>()->value;
}

std::string file_text(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::vector<fs::path> entries(const fs::path& dir) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".gsc") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST_CASE("a second run loads every cacheable node, outputs, records and files alike",
          "[stage_cache]") {
  const Registry reg = counting_registry();
  const fs::path dir = scratch_dir("cache_rerun");
  StageCache cache(dir / "cache", 0);
  runs().clear();
  const RunResult cold = run_cached(chain(reg, 2, 3), reg, cache, dir / "cold");
  CHECK(runs() == std::map<std::string, int>{{"src", 1}, {"mid", 1}, {"end", 1}});
  CHECK(cold.node("mid")->cache == "miss");
  const RunResult warm = run_cached(chain(reg, 2, 3), reg, cache, dir / "warm");
  CHECK(runs() == std::map<std::string, int>{{"src", 1}, {"mid", 1}, {"end", 1}});
  for (const char* id : {"src", "mid", "end"}) {
    CHECK(warm.node(id)->cache == "hit");
    CHECK(value(warm, id) == value(cold, id));
    CHECK(warm.node(id)->records == cold.node(id)->records);
  }
  CHECK(value(warm, "end") == 6.0);
  // The files the nodes wrote are restored into the new results folder.
  CHECK(file_text(dir / "warm/src/value.txt") == "2");
  CHECK(file_text(dir / "warm/end/scaled.txt") == "6");
}

TEST_CASE("a changed param reruns its node and what follows, nothing before", "[stage_cache]") {
  const Registry reg = counting_registry();
  const fs::path dir = scratch_dir("cache_param");
  StageCache cache(dir / "cache", 0);
  runs().clear();
  run_cached(chain(reg, 2, 3), reg, cache);
  const RunResult changed = run_cached(chain(reg, 2, 5), reg, cache);
  CHECK(runs() == std::map<std::string, int>{{"src", 1}, {"mid", 2}, {"end", 2}});
  CHECK(changed.node("src")->cache == "hit");
  CHECK(changed.node("mid")->cache == "miss");
  CHECK(value(changed, "end") == 10.0);
  // Both variants now stay cached side by side.
  run_cached(chain(reg, 2, 3), reg, cache);
  CHECK(runs()["mid"] == 2);
  // So does a float that differs in the 16th digit (the graph prints 15).
  run_cached(chain(reg, 2, 3.0000000000000004), reg, cache);
  CHECK(runs()["mid"] == 3);
}

TEST_CASE("the content of a path param's file is part of the key", "[stage_cache]") {
  const Registry reg = counting_registry();
  const fs::path dir = scratch_dir("cache_path");
  StageCache cache(dir / "cache", 0);
  const fs::path file = dir / "input.bin";
  std::ofstream(file) << "abc";
  runs().clear();
  CHECK(value(run_cached(chain(reg, 1, 1, file.string()), reg, cache), "end") == 4.0);
  run_cached(chain(reg, 1, 1, file.string()), reg, cache);
  CHECK(runs()["mid"] == 1);
  std::ofstream(file) << "abcdef";  // same name, new content
  CHECK(value(run_cached(chain(reg, 1, 1, file.string()), reg, cache), "end") == 7.0);
  CHECK(runs()["mid"] == 2);
  CHECK(runs()["src"] == 1);
}

TEST_CASE("the seed and uncacheable producers are part of the key", "[stage_cache]") {
  const Registry reg = counting_registry();
  const fs::path dir = scratch_dir("cache_seed");
  StageCache cache(dir / "cache", 0);
  runs().clear();
  run_cached(chain(reg, 2, 3), reg, cache, {}, 0);
  run_cached(chain(reg, 2, 3), reg, cache, {}, 1);
  CHECK(runs()["src"] == 2);
  // A live producer always runs; its consumers are still loaded when its params are the same.
  const RunResult a = run_cached(chain(reg, 2, 3, {}, "count.live"), reg, cache);
  const RunResult b = run_cached(chain(reg, 2, 3, {}, "count.live"), reg, cache);
  CHECK(runs()["src"] == 4);
  CHECK(a.node("src")->cache == "off");
  CHECK(b.node("mid")->cache == "hit");
}

TEST_CASE("a corrupt or truncated entry is detected, recomputed and replaced", "[stage_cache]") {
  const Registry reg = counting_registry();
  const fs::path dir = scratch_dir("cache_corrupt");
  StageCache cache(dir / "cache", 0);
  runs().clear();
  run_cached(chain(reg, 2, 3), reg, cache);
  const auto files = entries(dir / "cache");
  REQUIRE(files.size() == 3);
  // Flip one byte in the middle of every entry, then truncate every entry.
  for (const auto& f : files) {
    std::fstream io(f, std::ios::in | std::ios::out | std::ios::binary);
    io.seekg(static_cast<std::streamoff>(fs::file_size(f) / 2));
    char c = 0;
    io.get(c);
    io.seekp(static_cast<std::streamoff>(fs::file_size(f) / 2));
    io.put(static_cast<char>(c ^ 0x20));
  }
  const RunResult flipped = run_cached(chain(reg, 2, 3), reg, cache);
  CHECK(runs() == std::map<std::string, int>{{"src", 2}, {"mid", 2}, {"end", 2}});
  CHECK(value(flipped, "end") == 6.0);
  for (const auto& f : entries(dir / "cache")) fs::resize_file(f, fs::file_size(f) - 5);
  const RunResult truncated = run_cached(chain(reg, 2, 3), reg, cache);
  CHECK(runs() == std::map<std::string, int>{{"src", 3}, {"mid", 3}, {"end", 3}});
  CHECK(value(truncated, "end") == 6.0);
  // The recomputed entries are whole again.
  run_cached(chain(reg, 2, 3), reg, cache);
  CHECK(runs()["end"] == 3);
}

TEST_CASE("an entry that is a FIFO, a link to /dev/zero or longer than it says is recomputed",
          "[stage_cache]") {
  // Issue 33: a FIFO entry hung the run (opening it blocks), a link to /dev/zero was read to
  // 4.2 GB. Only a regular file, opened without following a link, read no further than its
  // header's size, is loaded.
  const Registry reg = counting_registry();
  const fs::path dir = scratch_dir("cache_hostile");
  StageCache cache(dir / "cache", 0);
  runs().clear();
  run_cached(chain(reg, 2, 3), reg, cache);
  const auto files = entries(dir / "cache");
  REQUIRE(files.size() == 3);
  fs::remove(files[0]);
  REQUIRE(::mkfifo(files[0].c_str(), 0644) == 0);
  fs::remove(files[1]);
  fs::create_symlink("/dev/zero", files[1]);
  std::ofstream(files[2], std::ios::app | std::ios::binary) << "more bytes than the header says";
  const RunResult r = run_cached(chain(reg, 2, 3), reg, cache);
  CHECK(runs() == std::map<std::string, int>{{"src", 2}, {"mid", 2}, {"end", 2}});
  CHECK(value(r, "end") == 6.0);
  // Each was replaced by a whole entry.
  for (const auto& f : entries(dir / "cache")) CHECK(fs::is_regular_file(fs::symlink_status(f)));
  run_cached(chain(reg, 2, 3), reg, cache);
  CHECK(runs()["end"] == 2);
}

TEST_CASE("an entry stored without files does not serve a run that writes files", "[stage_cache]") {
  const Registry reg = counting_registry();
  const fs::path dir = scratch_dir("cache_files");
  StageCache cache(dir / "cache", 0);
  runs().clear();
  run_cached(chain(reg, 2, 3), reg, cache);  // no results folder
  run_cached(chain(reg, 2, 3), reg, cache, dir / "out");
  CHECK(runs()["src"] == 2);
  CHECK(file_text(dir / "out/mid/scaled.txt") == "6");
  // Files left in the folder by an earlier run are not taken for the node's own.
  std::ofstream(dir / "out/mid/stale.txt") << "old";
  run_cached(chain(reg, 2, 7), reg, cache, dir / "out");
  run_cached(chain(reg, 2, 7), reg, cache, dir / "again");
  CHECK(fs::exists(dir / "again/mid/scaled.txt"));
  CHECK_FALSE(fs::exists(dir / "again/mid/stale.txt"));
}

TEST_CASE("eviction keeps the folder under its cap, least recently used first", "[stage_cache]") {
  const Registry reg = counting_registry();
  const fs::path dir = scratch_dir("cache_evict");
  StageCache unlimited(dir / "cache", 0);
  runs().clear();
  run_cached(chain(reg, 1, 1), reg, unlimited);
  uintmax_t one_run = 0;
  for (const auto& f : entries(dir / "cache")) one_run += fs::file_size(f);
  // Make the first run's entries old, then use them again: the hit makes them young.
  for (const auto& f : entries(dir / "cache"))
    fs::last_write_time(f, fs::file_time_type::clock::now() - std::chrono::hours(2));
  const auto first = entries(dir / "cache");
  run_cached(chain(reg, 1, 1), reg, unlimited);
  for (const auto& f : first)
    CHECK(fs::last_write_time(f) > fs::file_time_type::clock::now() - std::chrono::hours(1));
  // A cap of about one run's entries: a second, different chain evicts what was used least.
  StageCache capped(dir / "cache", one_run + 10);
  run_cached(chain(reg, 5, 5), reg, capped);
  uintmax_t total = 0;
  for (const auto& f : entries(dir / "cache")) total += fs::file_size(f);
  CHECK(total <= one_run + 10);
  // The newest entries (the second chain's) survive; the first chain's went first.
  runs().clear();
  run_cached(chain(reg, 5, 5), reg, capped);
  CHECK(runs()["end"] == 0);
  for (const auto& f : first) CHECK_FALSE(fs::exists(f));
}
