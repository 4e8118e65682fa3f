#include <fstream>
#include <map>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "runtime/batch.hpp"
#include "runtime/node.hpp"
#include "tests/json_file.hpp"
#include "tests/runtime/debug_nodes.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using gslift::test::debug_node;
using nlohmann::json;
namespace fs = std::filesystem;
using gslift::test::read_json;

namespace {

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

TEST_CASE("a failing capture is recorded and the others finish, reruns skip done ones", "[batch]") {
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
  // The second shard to finish merged both into _summary.json, rows by name.
  const json merged = read_json(dir / "out" / "_summary.json");
  CHECK(merged["done"] == 5);
  CHECK(merged["shards_merged"] == json::array({0, 1}));
  CHECK(merged["shard_count"] == 2);
  REQUIRE(merged["captures"].size() == 5);
  for (size_t i = 0; i < 5; ++i) CHECK(merged["captures"][i]["name"] == std::string(1, 'a' + i));
}

namespace {

EnvironmentLookup environment(std::map<std::string, std::string> vars) {
  return [vars](const std::string& name) -> std::optional<std::string> {
    auto it = vars.find(name);
    return it == vars.end() ? std::nullopt : std::optional<std::string>(it->second);
  };
}

std::string shard_error(std::map<std::string, std::string> vars, std::optional<int> count = {}) {
  try {
    shard_from_environment(environment(std::move(vars)), count);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("array tasks take their shard from Slurm or Kubernetes variables", "[batch]") {
  CHECK_FALSE(shard_from_environment(environment({}), std::nullopt));
  // --array=0-3: task 2 of 4.
  auto s = shard_from_environment(
      environment({{"SLURM_ARRAY_TASK_ID", "2"}, {"SLURM_ARRAY_TASK_COUNT", "4"}}), std::nullopt);
  REQUIRE(s);
  CHECK(s->shard.index == 2);
  CHECK(s->shard.count == 4);
  // --array=1-4: task 4 is the last shard, 3 of 4.
  s = shard_from_environment(environment({{"SLURM_ARRAY_TASK_ID", "4"},
                                          {"SLURM_ARRAY_TASK_MIN", "1"},
                                          {"SLURM_ARRAY_TASK_COUNT", "4"}}),
                             std::nullopt);
  CHECK(s->shard.index == 3);
  CHECK(s->shard.count == 4);
  // Slurm wins over Kubernetes when both are set.
  s = shard_from_environment(environment({{"SLURM_ARRAY_TASK_ID", "0"},
                                          {"SLURM_ARRAY_TASK_COUNT", "2"},
                                          {"JOB_COMPLETION_INDEX", "5"}}),
                             8);
  CHECK(s->shard.count == 2);
  // Kubernetes: the count from the option, else GSLIFT_SHARD_COUNT.
  s = shard_from_environment(environment({{"JOB_COMPLETION_INDEX", "5"}}), 8);
  CHECK(s->shard.index == 5);
  CHECK(s->shard.count == 8);
  s = shard_from_environment(
      environment({{"JOB_COMPLETION_INDEX", "1"}, {"GSLIFT_SHARD_COUNT", "3"}}), std::nullopt);
  CHECK(s->shard.index == 1);
  CHECK(s->shard.count == 3);
  CHECK_THAT(s->source, Catch::Contains("GSLIFT_SHARD_COUNT"));
}

TEST_CASE("a malformed scheduler variable names itself", "[batch]") {
  CHECK_THAT(shard_error({{"SLURM_ARRAY_TASK_ID", "x1"}, {"SLURM_ARRAY_TASK_COUNT", "4"}}),
             Catch::Contains("SLURM_ARRAY_TASK_ID") && Catch::Contains("'x1'"));
  CHECK_THAT(shard_error({{"SLURM_ARRAY_TASK_ID", "1"}, {"SLURM_ARRAY_TASK_COUNT", "4 "}}),
             Catch::Contains("SLURM_ARRAY_TASK_COUNT"));
  CHECK_THAT(shard_error({{"SLURM_ARRAY_TASK_ID", "1"}}),
             Catch::Contains("SLURM_ARRAY_TASK_COUNT"));
  // --array=0-6:2 has IDs 0, 2, 4, 6 and COUNT 4: ID 6 is outside 0..3.
  CHECK_THAT(shard_error({{"SLURM_ARRAY_TASK_ID", "6"}, {"SLURM_ARRAY_TASK_COUNT", "4"}}),
             Catch::Contains("contiguous range"));
  CHECK_THAT(shard_error({{"SLURM_ARRAY_TASK_ID", "-1"}, {"SLURM_ARRAY_TASK_COUNT", "4"}}),
             Catch::Contains("SLURM_ARRAY_TASK_ID"));
  CHECK_THAT(shard_error({{"JOB_COMPLETION_INDEX", "2"}}), Catch::Contains("--shard-count"));
  CHECK_THAT(shard_error({{"JOB_COMPLETION_INDEX", "2"}}, 2), Catch::Contains("0 <= index"));
  CHECK_THAT(shard_error({{"JOB_COMPLETION_INDEX", "2"}, {"GSLIFT_SHARD_COUNT", "zero"}}),
             Catch::Contains("GSLIFT_SHARD_COUNT"));
}

TEST_CASE("discovery lists the capture folders without a done-marker, by name", "[batch]") {
  const fs::path dir = test::scratch_dir("batch_discover");
  const fs::path in = dir / "incoming", out = dir / "out";
  for (const char* name : {"or_b", "or_a", ".or_copying", "_trash", "or_done", "or_failed"})
    fs::create_directories(in / name);
  std::ofstream(in / "notes.txt") << "a file, not a capture\n";
  fs::create_directories(out / "or_done");
  std::ofstream(out / "or_done" / "_DONE") << "{}\n";
  fs::create_directories(out / "or_failed");
  std::ofstream(out / "or_failed" / "_FAILED.json") << "{}\n";
  auto names = [](const std::vector<ManifestEntry>& m) {
    std::vector<std::string> n;
    for (const auto& e : m) n.push_back(e.name);
    return n;
  };
  const auto found = discover_captures(in, out);
  CHECK(names(found) == std::vector<std::string>{"or_a", "or_b", "or_failed"});
  CHECK(found[0].path == (in / "or_a").string());
  // A capture's index (and so its shard) depends on its name only.
  const auto again = discover_captures(in, dir / "elsewhere");
  CHECK(names(again) == std::vector<std::string>{"or_a", "or_b", "or_done", "or_failed"});
  CHECK(again[0].index == found[0].index);
  CHECK(again[3].index == found[2].index);
  // An output root inside the folder is not a capture.
  CHECK(names(discover_captures(in, in / "or_b")) ==
        std::vector<std::string>{"or_a", "or_done", "or_failed"});
  CHECK_THROWS_AS(discover_captures(in / "notes.txt", out), InputError);
  CHECK_THROWS_AS(discover_captures(dir / "missing", out), InputError);
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
