// End-to-end tests of the command line over the debug node types (gslift_debug_cli): the real
// cli_main, argument parsing, run.json, batch folders and exit codes.
#include <csignal>
#include <fstream>
#include <set>

#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "runtime/child_process.hpp"
#include "runtime/exit_codes.hpp"
#include "tests/cli/command.hpp"
#include "tests/json_file.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using gslift::test::run_command;
using nlohmann::json;
namespace fs = std::filesystem;
using gslift::test::read_json;

namespace {

const std::string kBinary = GSLIFT_DEBUG_BINARY;

fs::path write_text(const fs::path& file, const std::string& text) {
  std::ofstream(file) << text;
  return file;
}

std::string quoted(const fs::path& p) {
  return "'" + p.string() + "'";
}

const char* kSums = R"(graph: sums
params: {seed: 1}
nodes:
  a: {type: debug.constant, params: {value: 1.5}}
  r: {type: debug.random}
  s: {type: debug.add, in: {a: a.out, b: r.out}}
)";

}  // namespace

TEST_CASE("run writes run.json with the seed and --set values and says where", "[cli]") {
  const fs::path dir = test::scratch_dir("cli_run_ok");
  const fs::path graph = write_text(dir / "sums.yaml", kSums);
  const fs::path out = dir / "res";
  const auto r = run_command(kBinary + " run " + quoted(graph) + " --out " + quoted(out) +
                             " --seed 5 --threads=2 --set a.value=3 --log-level warn");
  INFO(r.output);
  REQUIRE(r.code == exit_code::kOk);
  CHECK(r.output.find("results: " + out.string() + " (run.json)") != std::string::npos);
  const json j = read_json(out / "run.json");
  CHECK(j["run"]["status"] == "ok");
  CHECK(j["run"]["seed"] == 5);
  CHECK(j["run"]["threads"] == 2);
  CHECK(j["graph"]["params"]["seed"] == 5);
  CHECK(j["graph"]["nodes"][0]["params"]["value"] == 3.0);

  // Without --seed the graph's seed param is the run seed; the random draw changes with it.
  const auto r1 = run_command(kBinary + " run " + quoted(graph) + " --out " + quoted(dir / "res1") +
                              " --log-level off");
  REQUIRE(r1.code == exit_code::kOk);
  const json j1 = read_json(dir / "res1" / "run.json");
  CHECK(j1["run"]["seed"] == 1);
  CHECK(j1["nodes"][1]["records"]["draw"] != j["nodes"][1]["records"]["draw"]);
}

TEST_CASE("run defaults its output folder to out/<graph name>", "[cli]") {
  const fs::path dir = test::scratch_dir("cli_run_default_out");
  write_text(dir / "sums.yaml", kSums);
  const auto r = run_command("cd " + quoted(dir) + " && " + kBinary + " run sums.yaml");
  INFO(r.output);
  REQUIRE(r.code == exit_code::kOk);
  CHECK(fs::exists(dir / "out" / "sums" / "run.json"));
  CHECK(r.output.find("results: out/sums (run.json)") != std::string::npos);
}

TEST_CASE("run maps failures to exit codes and names the node and its line", "[cli]") {
  const fs::path dir = test::scratch_dir("cli_run_fail");
  const fs::path failing = write_text(dir / "fail.yaml",
                                      "nodes:\n"
                                      "  a: {type: debug.constant}\n"
                                      "  f: {type: debug.fail, in: {in: a.out}, "
                                      "params: {message: out of memory}}\n");
  const auto r = run_command(kBinary + " run " + quoted(failing) + " --out " + quoted(dir / "o"));
  INFO(r.output);
  CHECK(r.code == exit_code::kNodeFailed);
  CHECK(r.output.find(failing.string() + ":3:3: node 'f' (debug.fail) failed: out of memory") !=
        std::string::npos);
  CHECK(read_json(dir / "o" / "run.json")["run"]["error"]["node"] == "f");

  const fs::path writer = write_text(dir / "write.yaml", "nodes:\n  w: {type: debug.write}\n");
  const auto bad = run_command(kBinary + " run " + quoted(writer) + " --input /data/bad_scene" +
                               " --out " + quoted(dir / "w"));
  INFO(bad.output);
  CHECK(bad.code == exit_code::kBadInput);
  CHECK(bad.output.find("/data/bad_scene: unreadable") != std::string::npos);

  // --out naming an existing file: bad input that names it, and the file is left as it was.
  const fs::path not_folder = write_text(dir / "not_a_folder", "keep");
  const auto file_out =
      run_command(kBinary + " run " + quoted(writer) + " --out " + quoted(not_folder));
  CHECK(file_out.code == exit_code::kBadInput);
  CHECK(file_out.output.find("--out " + not_folder.string() + " exists and is not a folder") !=
        std::string::npos);
  std::ifstream kept(not_folder);
  std::string text;
  kept >> text;
  CHECK(text == "keep");

  const fs::path invalid = write_text(dir / "invalid.yaml",
                                      "nodes:\n"
                                      "  a: {type: debug.constant, params: {valeu: 2}}\n"
                                      "  b: {type: debug.sleeep}\n");
  const auto inv = run_command(kBinary + " run " + quoted(invalid) + " --out " + quoted(dir / "i"));
  INFO(inv.output);
  CHECK(inv.code == exit_code::kInvalidGraph);
  // Every problem, each with file:line:col.
  CHECK(inv.output.find(invalid.string() + ":2:") != std::string::npos);
  CHECK(inv.output.find(invalid.string() + ":3:") != std::string::npos);
  CHECK(inv.output.find("2 errors") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "i"));

  const auto missing = run_command(kBinary + " run " + quoted(dir / "absent.yaml"));
  CHECK(missing.code == exit_code::kBadInput);
}

TEST_CASE("usage errors exit 2 with a hint", "[cli]") {
  const auto option = run_command(kBinary + " run g.yaml --thread 2");
  CHECK(option.code == exit_code::kUsage);
  CHECK(option.output.find("unknown option '--thread' (did you mean '--threads'?)") !=
        std::string::npos);
  CHECK(run_command(kBinary + " run g.yaml --threads two").code == exit_code::kUsage);
  // Absurd thread counts are usage errors naming the bound, not a pthread abort or a crash.
  for (const char* n : {"5000", "10000000", "99999999999999999999"}) {
    const auto huge = run_command(kBinary + " run g.yaml --threads " + n);
    CHECK(huge.code == exit_code::kUsage);
    CHECK(huge.output.find("--threads expects an integer >= 0 and <= 1024") != std::string::npos);
  }
  CHECK(run_command(kBinary + " run").code == exit_code::kUsage);
  CHECK(run_command(kBinary + " run g.yaml --out").code == exit_code::kUsage);
  CHECK(run_command(kBinary + " run g.yaml --log-level loud").code == exit_code::kUsage);
  const auto type = run_command(kBinary + " nodes debug.sleap");
  CHECK(type.code == exit_code::kUsage);
  CHECK(type.output.find("did you mean 'debug.sleep'?") != std::string::npos);
  CHECK(run_command(kBinary + " batch m.txt g.yaml").code == exit_code::kUsage);  // no --out
  CHECK(run_command(kBinary + " batch m.txt g.yaml --out o --shard 2/2").code == exit_code::kUsage);
}

TEST_CASE("validate --print prints the resolved graph", "[cli]") {
  const fs::path dir = test::scratch_dir("cli_validate_print");
  const fs::path graph = write_text(dir / "sums.yaml", kSums);
  const auto ok = run_command(kBinary + " validate " + quoted(graph));
  CHECK(ok.code == exit_code::kOk);
  CHECK(ok.output.find("ok: graph 'sums' (3 nodes)") != std::string::npos);
  const auto printed =
      run_command(kBinary + " validate " + quoted(graph) + " --print --set a.value=7");
  INFO(printed.output);
  CHECK(printed.code == exit_code::kOk);
  CHECK(printed.output.find("  a:\n    type: debug.constant\n    params: {value: 7.0}\n") !=
        std::string::npos);
  CHECK(printed.output.find("    in: {a: a.out, b: r.out}\n") != std::string::npos);
}

TEST_CASE("SIGINT stops a run cleanly with exit code 130 and a record", "[cli]") {
  // The signal is sent once node s is running (its partial file exists; the handlers are
  // installed before any node starts), and s would sleep a minute on its own: no timing decides
  // the outcome. The shell gives up waiting if gslift exits before writing the file.
  const fs::path dir = test::scratch_dir("cli_sigint");
  const fs::path graph = write_text(dir / "slow.yaml",
                                    "nodes:\n"
                                    "  s: {type: debug.sleep, params: {ms: 60000, write: true}}\n"
                                    "  t: {type: debug.sleep, in: {in: s.out}}\n");
  const fs::path out = dir / "o";
  const auto r =
      run_command("sh -c '" + kBinary + " run " + graph.string() + " --out " + out.string() +
                  " & pid=$!; while [ ! -e " + (out / "s" / "partial.txt").string() +
                  " ] && kill -0 $pid 2>/dev/null; do sleep 0.01; done; "
                  "kill -INT $pid; wait $pid; exit $?'");
  INFO(r.output);
  CHECK(r.code == exit_code::kInterrupted);
  const json j = read_json(out / "run.json");
  CHECK(j["run"]["status"] == "interrupted");
  CHECK(j["nodes"][0]["status"] == "cancelled");
  CHECK(j["nodes"][1]["status"] == "pending");
  // The cancelled node's half-written folder is gone.
  CHECK_FALSE(fs::exists(out / "s"));
}

TEST_CASE("batch runs every capture, records failures, skips done ones and shards", "[cli]") {
  const fs::path dir = test::scratch_dir("cli_batch");
  const fs::path graph = write_text(dir / "write.yaml", "nodes:\n  w: {type: debug.write}\n");
  const fs::path manifest =
      write_text(dir / "manifest.txt", "# three captures\nor_1\nbad_2\nor_3\n");
  const fs::path out = dir / "out";
  const std::string cmd =
      kBinary + " batch " + quoted(manifest) + " " + quoted(graph) + " --out " + quoted(out);
  const auto first = run_command(cmd);
  INFO(first.output);
  CHECK(first.code == exit_code::kBatchPartial);
  CHECK(first.output.find("2 done, 0 skipped, 1 failed") != std::string::npos);
  CHECK(fs::exists(out / "or_1" / "_DONE"));
  CHECK(fs::exists(out / "or_3" / "w" / "input.txt"));
  CHECK(fs::exists(out / "bad_2" / "_FAILED.json"));
  CHECK(read_json(out / "_summary.json")["failed"] == 1);

  const auto again = run_command(cmd);
  CHECK(again.code == exit_code::kBatchPartial);
  CHECK(again.output.find("0 done, 2 skipped, 1 failed") != std::string::npos);

  const fs::path good = write_text(dir / "good.txt", "a\nb\nc\n");
  const std::string shard = kBinary + " batch " + quoted(good) + " " + quoted(graph) + " --out " +
                            quoted(dir / "sharded") + " --shard ";
  CHECK(run_command(shard + "1/2").code == exit_code::kOk);
  CHECK(fs::exists(dir / "sharded" / "b" / "_DONE"));
  CHECK_FALSE(fs::exists(dir / "sharded" / "a"));
  CHECK(run_command(shard + "0/2").code == exit_code::kOk);
  CHECK(fs::exists(dir / "sharded" / "a" / "_DONE"));
  CHECK(fs::exists(dir / "sharded" / "c" / "_DONE"));
}

TEST_CASE("sweep runs the grid over seeds through the cache, failed runs become rows", "[cli]") {
  const fs::path dir = test::scratch_dir("cli_sweep");
  // s = a + r: `a` takes the grid's value, `r` draws from the seed, `f` is swapped for a failing
  // stage in half of the grid.
  const fs::path graph = write_text(dir / "sweep.yaml", R"(graph: sweep
nodes:
  a: {type: debug.constant, params: {value: 1}}
  r: {type: debug.random}
  s: {type: debug.add, in: {a: a.out, b: r.out}}
  f: {type: debug.constant}
)");
  const fs::path out = dir / "out";
  const std::string cmd = kBinary + " sweep " + quoted(graph) +
                          " --grid a.value=1,2 --grid f.type=debug.constant,debug.fail" +
                          " --seeds 3-4 --out " + quoted(out);
  const auto r = run_command(cmd);
  INFO(r.output);
  CHECK(r.code == exit_code::kBatchPartial);  // the debug.fail half failed; the rest is done
  const json sweep = read_json(out / "sweep.json");
  REQUIRE(sweep["runs"].size() == 8);  // 2 values x 2 stages x 2 seeds
  CHECK(sweep["seeds"] == json::array({3, 4}));
  int failed = 0;
  for (const auto& run : sweep["runs"]) {
    const bool fails = run["params"]["f.type"] == "debug.fail";
    CHECK(run["status"] == (fails ? "failed" : "ok"));
    if (fails) {
      ++failed;
      CHECK(run["error"].get<std::string>().find("node 'f' failed: boom") != std::string::npos);
      continue;
    }
    // s = a + the seed's draw, read back from the run's own run.json.
    const json record = read_json(out / run["dir"].get<std::string>() / "run.json");
    CHECK(record["run"]["seed"] == run["seed"]);
    const double a = std::stod(run["params"]["a.value"].get<std::string>());
    CHECK(run["metrics"]["r.draw"].get<double>() == record["nodes"][1]["records"]["draw"]);
    CHECK(run["node_wall_s"].contains("s"));
    CHECK(a >= 1);
  }
  CHECK(failed == 4);
  // The summary groups over the two seeds: mean and sample std of the draw, by hand.
  const auto& s0 = sweep["summary"][0];
  CHECK(s0["params"]["a.value"] == "1");
  CHECK(s0["n"] == 2);
  const double d3 = sweep["runs"][0]["metrics"]["r.draw"],
               d4 = sweep["runs"][1]["metrics"]["r.draw"];
  CHECK(s0["metrics"]["r.draw"]["mean"].get<double>() == Approx((d3 + d4) / 2));
  CHECK(s0["metrics"]["r.draw"]["std"].get<double>() == Approx(std::abs(d3 - d4) / std::sqrt(2.0)));
  CHECK(sweep["summary"][1]["failed"] == 2);
  // The random node's results are shared through the cache by runs with the same seed: the
  // second grid point (a.value=1, f swapped) loads `r`, and a.value=2 loads it too.
  const json later = read_json(out / "runs/0004/run.json");
  CHECK(later["nodes"][1]["id"] == "r");
  CHECK(later["nodes"][1]["cache"] == "hit");
  std::ifstream csv(out / "results.csv");
  std::string header;
  std::getline(csv, header);
  CHECK(header.rfind("run,seed,status,error,a.value,f.type,total_s,peak_rss_mb", 0) == 0);
  CHECK(fs::exists(out / "summary.csv"));

  // {seed} in a --set value is each run's seed.
  const auto templated = run_command(kBinary + " sweep " + quoted(graph) +
                                     " --grid f.type=debug.constant --set 'a.value={seed}'" +
                                     " --seeds 5,7 --out " + quoted(dir / "templated"));
  INFO(templated.output);
  REQUIRE(templated.code == exit_code::kOk);
  for (const auto& [run, seed] : {std::pair{"runs/0000", 5}, std::pair{"runs/0001", 7}})
    CHECK(read_json(dir / "templated" / run / "run.json")["graph"]["nodes"][0]["params"]["value"] ==
          double(seed));

  // A misspelt grid param is one invalid-graph error before anything runs.
  const auto bad = run_command(kBinary + " sweep " + quoted(graph) + " --grid a.valeu=1,2 --out " +
                               quoted(dir / "bad"));
  CHECK(bad.code == exit_code::kInvalidGraph);
  CHECK(bad.output.find("did you mean 'value'") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "bad" / "runs"));

  // Grids that cannot be a sweep are usage errors before anything runs: a param on two axes
  // (the second replaced the first silently) and 10^6 grid points (5.5 GB of plan, then exit 70).
  const auto twice =
      run_command(kBinary + " sweep " + quoted(graph) +
                  " --grid a.value=1 --grid a.value=2 --out " + quoted(dir / "twice"));
  CHECK(twice.code == exit_code::kUsage);
  CHECK(twice.output.find("--grid a.value is given twice") != std::string::npos);
  std::string thousand = "0";
  for (int i = 1; i < 1000; ++i) thousand += "," + std::to_string(i);
  const auto huge =
      run_command(kBinary + " sweep " + quoted(graph) + " --grid a.value=" + thousand +
                  " --grid f.value=" + thousand + " --out " + quoted(dir / "huge"));
  CHECK(huge.code == exit_code::kUsage);
  CHECK(huge.output.find("more than 10000 runs") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "huge" / "runs"));
}

TEST_CASE(
    "sweep over seeds alone runs the graph once per seed, neither grid nor seeds is a usage "
    "error",
    "[cli]") {
  const fs::path dir = test::scratch_dir("cli_sweep_seeds");
  const fs::path graph = write_text(dir / "seeds.yaml", R"(graph: seeds
nodes:
  r: {type: debug.random}
)");
  const auto none =
      run_command(kBinary + " sweep " + quoted(graph) + " --out " + quoted(dir / "none"));
  CHECK(none.code == exit_code::kUsage);
  CHECK(none.output.find("--grid NODE.PARAM=V1,V2, --seeds LIST or --inputs SET") !=
        std::string::npos);
  const fs::path out = dir / "out";
  const auto r =
      run_command(kBinary + " sweep " + quoted(graph) + " --seeds 0-2 --out " + quoted(out));
  INFO(r.output);
  REQUIRE(r.code == 0);
  const json sweep = read_json(out / "sweep.json");
  REQUIRE(sweep["runs"].size() == 3);
  std::set<double> draws;  // each seed's own random stream
  for (const auto& run : sweep["runs"]) {
    CHECK(run["status"] == "ok");
    const json record = read_json(out / run["dir"].get<std::string>() / "run.json");
    for (const auto& n : record["nodes"])
      if (n["id"] == "r") draws.insert(n["records"]["draw"].get<double>());
  }
  CHECK(draws.size() == 3);
}

TEST_CASE("two runs sharing a cache folder at once both finish and leave whole entries", "[cli]") {
  const fs::path dir = test::scratch_dir("cli_shared_cache");
  const fs::path graph = write_text(dir / "sums.yaml", kSums);
  const std::string run = kBinary + " run " + quoted(graph) + " --log-level warn --cache-dir " +
                          quoted(dir / "cache") + " --out ";
  // Both start together and store the same keys; each writes under its own temporary name.
  const auto both =
      run_command("(" + run + quoted(dir / "a") + " & " + run + quoted(dir / "b") + " & wait)");
  INFO(both.output);
  CHECK(read_json(dir / "a" / "run.json")["run"]["status"] == "ok");
  CHECK(read_json(dir / "b" / "run.json")["run"]["status"] == "ok");
  // A third run loads every node: the entries are whole, and no temporary file is left.
  REQUIRE(run_command(run + quoted(dir / "c")).code == exit_code::kOk);
  const json c = read_json(dir / "c" / "run.json");
  for (const auto& n : c["nodes"]) CHECK(n["cache"] == "hit");
  CHECK(c["nodes"][2]["records"] == read_json(dir / "a" / "run.json")["nodes"][2]["records"]);
  for (const auto& e : fs::directory_iterator(dir / "cache"))
    CHECK(e.path().filename().string().find(".tmp-") == std::string::npos);
}

TEST_CASE("batch takes its shard from Slurm or Kubernetes variables, --shard wins", "[cli]") {
  const fs::path dir = test::scratch_dir("cli_batch_env");
  const fs::path graph = write_text(dir / "write.yaml", "nodes:\n  w: {type: debug.write}\n");
  const fs::path manifest = write_text(dir / "m.txt", "a\nb\nc\nd\n");
  const auto batch = [&](const std::string& env, const std::string& out,
                         const std::string& extra = {}) {
    return run_command("env -u SLURM_ARRAY_TASK_ID -u JOB_COMPLETION_INDEX " + env + " " + kBinary +
                       " batch " + quoted(manifest) + " " + quoted(graph) + " --out " +
                       quoted(dir / out) + extra);
  };
  // --array=1-4, task 3: shard 2/4 takes c.
  auto r = batch("SLURM_ARRAY_TASK_ID=3 SLURM_ARRAY_TASK_MIN=1 SLURM_ARRAY_TASK_COUNT=4", "slurm");
  INFO(r.output);
  CHECK(r.code == exit_code::kOk);
  CHECK(r.output.find("shard 2/4 from SLURM_ARRAY_TASK_ID=3") != std::string::npos);
  CHECK(fs::exists(dir / "slurm" / "c" / "_DONE"));
  CHECK_FALSE(fs::exists(dir / "slurm" / "a"));
  // --shard wins over the environment.
  r = batch("SLURM_ARRAY_TASK_ID=0 SLURM_ARRAY_TASK_COUNT=4", "explicit", " --shard 1/4");
  CHECK(r.code == exit_code::kOk);
  CHECK(fs::exists(dir / "explicit" / "b" / "_DONE"));
  CHECK_FALSE(fs::exists(dir / "explicit" / "a"));
  // Kubernetes Indexed Job: the count from --shard-count or GSLIFT_SHARD_COUNT.
  r = batch("JOB_COMPLETION_INDEX=3", "k8s", " --shard-count 4");
  CHECK(r.code == exit_code::kOk);
  CHECK(fs::exists(dir / "k8s" / "d" / "_DONE"));
  CHECK_FALSE(fs::exists(dir / "k8s" / "a"));
  r = batch("JOB_COMPLETION_INDEX=0 GSLIFT_SHARD_COUNT=2", "k8s_env");
  CHECK(r.code == exit_code::kOk);
  CHECK(fs::exists(dir / "k8s_env" / "c" / "_DONE"));
  CHECK_FALSE(fs::exists(dir / "k8s_env" / "b"));
  // A malformed value is a usage error naming the variable; nothing runs.
  r = batch("SLURM_ARRAY_TASK_ID=two SLURM_ARRAY_TASK_COUNT=4", "bad");
  CHECK(r.code == exit_code::kUsage);
  CHECK(r.output.find("SLURM_ARRAY_TASK_ID") != std::string::npos);
  r = batch("JOB_COMPLETION_INDEX=1", "bad");
  CHECK(r.code == exit_code::kUsage);
  CHECK(r.output.find("--shard-count") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "bad"));
}

TEST_CASE("batch --discover runs the capture folders without a result, then only new ones",
          "[cli]") {
  const fs::path dir = test::scratch_dir("cli_batch_discover");
  const fs::path graph = write_text(dir / "write.yaml", "nodes:\n  w: {type: debug.write}\n");
  for (const char* name : {"or_mon", "or_tue", ".or_copying"})
    fs::create_directories(dir / "in" / name);
  const std::string cmd = kBinary + " batch --discover " + quoted(dir / "in") + " " +
                          quoted(graph) + " --out " + quoted(dir / "out");
  auto r = run_command(cmd);
  INFO(r.output);
  CHECK(r.code == exit_code::kOk);
  CHECK(r.output.find("discovered 2 capture(s)") != std::string::npos);
  CHECK(fs::exists(dir / "out" / "or_mon" / "_DONE"));
  CHECK(fs::exists(dir / "out" / "or_tue" / "_DONE"));
  CHECK_FALSE(fs::exists(dir / "out" / ".or_copying"));
  // The next night: one new capture, and the copy finished (renamed into place).
  fs::create_directories(dir / "in" / "or_wed");
  fs::rename(dir / "in" / ".or_copying", dir / "in" / "or_thu");
  r = run_command(cmd);
  CHECK(r.code == exit_code::kOk);
  CHECK(r.output.find("discovered 2 capture(s)") != std::string::npos);
  CHECK(r.output.find("2 done, 0 skipped, 0 failed") != std::string::npos);
  const json summary = read_json(dir / "out" / "_summary.json");
  REQUIRE(summary["captures"].size() == 2);
  CHECK(summary["captures"][0]["name"] == "or_thu");
  CHECK(summary["captures"][1]["name"] == "or_wed");
  // Nothing new: nothing runs, success.
  r = run_command(cmd);
  CHECK(r.code == exit_code::kOk);
  CHECK(r.output.find("discovered 0 capture(s)") != std::string::npos);
  // --discover takes GRAPH only.
  CHECK(run_command(cmd + " extra.yaml").code == exit_code::kUsage);
}

TEST_CASE("a capture that aborts its process fails alone with the signal, the batch goes on",
          "[cli]") {
  // Each capture is a `gslift run` child process (issue 33): debug.write aborts the process on an
  // input naming "abort", as a library's assertion would. In one process it took the batch down.
  const fs::path dir = test::scratch_dir("cli_batch_crash");
  const fs::path graph = write_text(dir / "write.yaml", "nodes:\n  w: {type: debug.write}\n");
  const fs::path manifest = write_text(dir / "m.txt", "or_1\nabort_2\nor_3\n");
  const fs::path out = dir / "out";
  const auto r = run_command(kBinary + " batch " + quoted(manifest) + " " + quoted(graph) +
                             " --out " + quoted(out));
  INFO(r.output);
  CHECK(r.code == exit_code::kBatchPartial);
  CHECK(r.output.find("2 done, 0 skipped, 1 failed") != std::string::npos);
  CHECK(fs::exists(out / "or_1" / "_DONE"));
  CHECK(fs::exists(out / "or_3" / "w" / "input.txt"));
  const json failed = read_json(out / "abort_2" / "_FAILED.json");
  CHECK_THAT(failed["error"].get<std::string>(),
             Catch::Contains("killed by signal " + std::to_string(SIGABRT)));
  CHECK(read_json(out / "_summary.json")["failed"] == 1);
}

TEST_CASE("a capture name as long as a file name may be runs like any other", "[cli]") {
  // 250 bytes is a legal folder name on ext4, but `.<name>.partial` is 9 bytes longer than the
  // limit: the batch exited 70 and stopped (issue 33).
  const fs::path dir = test::scratch_dir("cli_batch_long_name");
  const fs::path graph = write_text(dir / "write.yaml", "nodes:\n  w: {type: debug.write}\n");
  const std::string long_name(250, 'c');
  const fs::path manifest = write_text(dir / "m.txt", long_name + "\nor_2\n");
  const fs::path out = dir / "out";
  const auto r = run_command(kBinary + " batch " + quoted(manifest) + " " + quoted(graph) +
                             " --out " + quoted(out));
  INFO(r.output);
  CHECK(r.code == exit_code::kOk);
  CHECK(fs::exists(out / long_name / "_DONE"));
  CHECK(fs::exists(out / long_name / "w" / "input.txt"));
  CHECK(fs::exists(out / "or_2" / "_DONE"));
}

TEST_CASE("a run killed near its end leaves a record saying running, not the old run's", "[cli]") {
  const fs::path dir = test::scratch_dir("cli_run_killed");
  const fs::path out = dir / "o";
  REQUIRE(run_command(kBinary + " run " + quoted(write_text(dir / "sums.yaml", kSums)) + " --out " +
                      quoted(out))
              .code == exit_code::kOk);
  REQUIRE(read_json(out / "run.json")["run"]["status"] == "ok");
  // The second run into the same folder is killed (-9) once its node is running; the node would
  // sleep a minute on its own, so no timing decides the outcome.
  const fs::path slow = write_text(
      dir / "slow.yaml", "nodes:\n  s: {type: debug.sleep, params: {ms: 60000, write: true}}\n");
  const auto r =
      run_command("sh -c '" + kBinary + " run " + slow.string() + " --out " + out.string() +
                  " & pid=$!; while [ ! -e " + (out / "s" / "partial.txt").string() +
                  " ] && kill -0 $pid 2>/dev/null; do sleep 0.01; done; "
                  "kill -9 $pid; wait $pid; exit $?'");
  INFO(r.output);
  CHECK(r.code == 128 + SIGKILL);
  const json j = read_json(out / "run.json");
  CHECK(j["run"]["status"] == "running");
  CHECK(j["graph"]["nodes"][0]["id"] == "s");  // the new run's graph, not the old one's
}

TEST_CASE("a run removes only its own dead temporaries, in the folders it writes", "[cli]") {
  const fs::path dir = test::scratch_dir("cli_run_temporaries");
  const fs::path graph = write_text(dir / "write.yaml", "nodes:\n  w: {type: debug.write}\n");
  const fs::path out = dir / "o";
  const std::string run = kBinary + " run " + quoted(graph) + " --input x --out " + quoted(out);
  REQUIRE(run_command(run).code == exit_code::kOk);
  // A process id that is gone: a child that has been reaped.
  const int dead = [] {
    const pid_t pid = fork();
    if (pid == 0) _exit(0);
    waitpid(pid, nullptr, 0);
    return static_cast<int>(pid);
  }();
  const std::string live = std::to_string(getpid());  // another run still writing
  const std::vector<fs::path> kept = {
      out / "important.tmp-7-7.docx",                                       // the user's
      out / ("run.gslift.tmp-" + live + "-0.json"),                         // a live run's
      out / "notes" / ("n.gslift.tmp-" + std::to_string(dead) + "-1.png"),  // not gslift's folder
  };
  const std::vector<fs::path> removed = {
      out / ("run.gslift.tmp-" + std::to_string(dead) + "-3.json"),
      out / "w" / "deep" / ("x.gslift.tmp-" + std::to_string(dead) + "-2.png"),
  };
  for (const auto& f : kept) fs::create_directories(f.parent_path()), write_text(f, "keep");
  for (const auto& f : removed) fs::create_directories(f.parent_path()), write_text(f, "half");
  const auto r = run_command(run);
  INFO(r.output);
  CHECK(r.code == exit_code::kOk);
  for (const auto& f : kept) CHECK(fs::exists(f));
  for (const auto& f : removed) CHECK_FALSE(fs::exists(f));
}

TEST_CASE("run refuses an --out that holds files but no run.json", "[cli]") {
  const fs::path dir = test::scratch_dir("cli_run_foreign_out");
  const fs::path graph = write_text(dir / "sums.yaml", kSums);
  const fs::path home = dir / "home";
  fs::create_directories(home);
  write_text(home / "thesis.tex", "mine");
  const auto r = run_command(kBinary + " run " + quoted(graph) + " --out " + quoted(home));
  INFO(r.output);
  CHECK(r.code == exit_code::kBadInput);
  CHECK(r.output.find("holds no run.json") != std::string::npos);
  CHECK_FALSE(fs::exists(home / "run.json"));
  CHECK_FALSE(fs::exists(home / "a"));
}

TEST_CASE("a child run reports its own peak memory, not its large parent's", "[cli]") {
  // The kernel carries the address space's peak that exec replaces into ru_maxrss, and a child
  // of posix_spawn runs in its parent's until it execs: sweep children reported the sweep's peak
  // (issue 33). This process grows to 600 MB first; the child's graph needs a few MB.
  const fs::path dir = test::scratch_dir("cli_child_peak");
  const fs::path graph = write_text(dir / "sums.yaml", kSums);
  std::vector<char> ballast(600u << 20);
  for (size_t i = 0; i < ballast.size(); i += 4096) ballast[i] = 1;
  const ChildRun child =
      run_child_process({kBinary, "run", graph.string(), "--out", (dir / "o").string(),
                         "--no-cache", "--log-level", "warn"});
  REQUIRE(child.started);
  CHECK(child.peak_mb >= 600);  // what wait4 says: the parent's
  const double own = read_json(dir / "o" / "run.json")["run"]["peak_rss_mb"].get<double>();
  CHECK(own > 0);
  CHECK(own < 200);
  CHECK(ballast[4096] == 1);
}
