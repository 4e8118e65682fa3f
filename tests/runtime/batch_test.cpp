#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "runtime/batch.hpp"
#include "runtime/node.hpp"
#include "tests/runtime/debug_nodes.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using gslift::test::debug_node;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

json read_json(const fs::path& f) {
  std::ifstream in(f);
  return json::parse(in);
}

fs::path write_manifest(const fs::path& dir, const std::string& text) {
  std::ofstream(dir / "manifest.txt") << text;
  return dir / "manifest.txt";
}

// Runs a one-node graph (debug.write) with the capture path as run input; "bad" captures fail.
struct CountingRunner {
  const Registry reg = test::debug_registry();
  std::vector<std::string> ran;
  RunResult operator()(const ManifestEntry& e, const fs::path& out) {
    ran.push_back(e.name);
    Graph g;
    g.name = "write";
    g.nodes = {debug_node(reg, "w", "debug.write")};
    RunOptions opt;
    opt.out_dir = out;
    opt.run_input = e.path;
    return execute(g, reg, opt);
  }
};

}  // namespace

TEST_CASE("manifests skip comments and blanks and resolve paths beside the manifest", "[batch]") {
  const fs::path dir = test::scratch_dir("batch_manifest");
  const auto m = read_manifest(
      write_manifest(dir, "# captures\n\n  or_a/  \n/data/or_b # the second\nembedded:or\n"));
  REQUIRE(m.size() == 3);
  CHECK(m[0].path == (dir / "or_a/").string());
  CHECK(m[0].name == "or_a");
  CHECK(m[0].line == 3);
  CHECK(m[0].index == 0);
  CHECK(m[1].path == "/data/or_b");
  CHECK(m[1].name == "or_b");
  CHECK(m[1].line == 4);
  CHECK(m[2].path == "embedded:or");
  CHECK(m[2].name == "embedded_or");
  CHECK(m[2].index == 2);

  write_manifest(dir, "x/scene\ny/scene\n");
  try {
    read_manifest(dir / "manifest.txt");
    FAIL("duplicate output names were accepted");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()) == (dir / "manifest.txt").string() +
                                       ":2: capture 'y/scene' has the same output folder name "
                                       "'scene' as line 1");
  }
  CHECK_THROWS_AS(read_manifest(dir / "absent.txt"), InputError);
}

TEST_CASE("shards split captures by index modulo count", "[batch]") {
  const Shard s = parse_shard("1/3");
  CHECK(s.index == 1);
  CHECK(s.count == 3);
  CHECK(s.takes(1));
  CHECK(s.takes(4));
  CHECK_FALSE(s.takes(0));
  CHECK_FALSE(s.takes(5));
  CHECK_THROWS_AS(parse_shard("3/3"), std::invalid_argument);
  CHECK_THROWS_AS(parse_shard("1"), std::invalid_argument);
  CHECK_THROWS_AS(parse_shard("1/x"), std::invalid_argument);
  CHECK_THROWS_AS(parse_shard("-1/2"), std::invalid_argument);
  CHECK_THROWS_AS(parse_shard("0/0"), std::invalid_argument);
}

TEST_CASE("a failing capture is recorded and the others finish; reruns skip done ones", "[batch]") {
  const fs::path dir = test::scratch_dir("batch_run");
  const auto manifest = read_manifest(write_manifest(dir, "cap1\nbad_cap\ncap3\n"));
  const fs::path out = dir / "out";
  CountingRunner runner;
  auto run = [&](const ManifestEntry& e, const fs::path& o) { return runner(e, o); };

  const BatchSummary first = run_batch(manifest, out, Shard{}, run);
  REQUIRE(first.captures.size() == 3);
  CHECK(first.count(CaptureStatus::Done) == 2);
  CHECK(first.count(CaptureStatus::Failed) == 1);
  CHECK(first.captures[1].status == CaptureStatus::Failed);
  CHECK(first.captures[1].error.find("node 'w' (debug.write) failed") != std::string::npos);
  for (const char* name : {"cap1", "cap3"}) {
    CHECK(fs::exists(out / name / "_DONE"));
    CHECK(fs::exists(out / name / "run.json"));
    std::ifstream in(out / name / "w" / "input.txt");
    std::string text;
    std::getline(in, text);
    CHECK(text == (dir / name).string());
    CHECK(read_json(out / name / "_DONE")["capture"] == name);
  }
  const json failed = read_json(out / "bad_cap" / "_FAILED.json");
  CHECK(failed["kind"] == "bad-input");
  CHECK(failed["input"] == (dir / "bad_cap").string());
  CHECK_FALSE(fs::exists(out / "bad_cap" / "_DONE"));
  // No temporary folder is left behind.
  for (const auto& e : fs::directory_iterator(out))
    CHECK(e.path().filename().string().find(".partial") == std::string::npos);
  const json summary = read_json(out / "_summary.json");
  CHECK(summary["done"] == 2);
  CHECK(summary["failed"] == 1);
  CHECK(summary["captures"][1]["status"] == "failed");
  CHECK(first.table().find("2 done, 0 skipped, 1 failed") != std::string::npos);

  runner.ran.clear();
  const BatchSummary second = run_batch(manifest, out, Shard{}, run);
  CHECK(runner.ran == std::vector<std::string>{"bad_cap"});
  CHECK(second.count(CaptureStatus::Skipped) == 2);
  CHECK(second.count(CaptureStatus::Failed) == 1);
}

TEST_CASE("shards of one manifest run disjoint captures that cover it", "[batch]") {
  const fs::path dir = test::scratch_dir("batch_shard");
  const auto manifest = read_manifest(write_manifest(dir, "a\nb\nc\nd\ne\n"));
  CountingRunner r0, r1;
  const BatchSummary s0 =
      run_batch(manifest, dir / "out", parse_shard("0/2"),
                [&](const ManifestEntry& e, const fs::path& o) { return r0(e, o); });
  const BatchSummary s1 =
      run_batch(manifest, dir / "out", parse_shard("1/2"),
                [&](const ManifestEntry& e, const fs::path& o) { return r1(e, o); });
  CHECK(r0.ran == std::vector<std::string>{"a", "c", "e"});
  CHECK(r1.ran == std::vector<std::string>{"b", "d"});
  CHECK(s0.count(CaptureStatus::Done) == 3);
  CHECK(s1.count(CaptureStatus::Done) == 2);
  CHECK(fs::exists(dir / "out" / "_summary-0of2.json"));
  CHECK(fs::exists(dir / "out" / "_summary-1of2.json"));
}

TEST_CASE("a runner that throws fails only its capture", "[batch]") {
  const fs::path dir = test::scratch_dir("batch_throw");
  const auto manifest = read_manifest(write_manifest(dir, "x\ny\n"));
  CountingRunner ok;
  const BatchSummary s =
      run_batch(manifest, dir / "out", Shard{}, [&](const ManifestEntry& e, const fs::path& o) {
        if (e.name == "x") throw std::runtime_error("graph invalid for x");
        return ok(e, o);
      });
  CHECK(s.captures[0].status == CaptureStatus::Failed);
  CHECK(s.captures[0].error == "graph invalid for x");
  CHECK(read_json(dir / "out" / "x" / "_FAILED.json")["error"] == "graph invalid for x");
  CHECK(s.captures[1].status == CaptureStatus::Done);
}

TEST_CASE("an interruption stops the batch and removes the unfinished capture", "[batch]") {
  const fs::path dir = test::scratch_dir("batch_interrupt");
  const auto manifest = read_manifest(write_manifest(dir, "x\ny\n"));
  std::atomic<bool> flag{false};
  CountingRunner inner;
  const BatchSummary s = run_batch(
      manifest, dir / "out", Shard{},
      [&](const ManifestEntry& e, const fs::path& o) {
        flag = true;  // as if SIGINT arrived while x was running
        RunResult r = inner(e, o);
        r.status = RunStatus::Interrupted;
        return r;
      },
      &flag);
  CHECK(s.interrupted);
  REQUIRE(s.captures.size() == 1);
  CHECK(s.captures[0].status == CaptureStatus::Interrupted);
  CHECK_FALSE(fs::exists(dir / "out" / "x"));
  CHECK_FALSE(fs::exists(dir / "out" / ".x.partial"));
  CHECK(inner.ran == std::vector<std::string>{"x"});
}
