// End-to-end tests of the gslift executable with the built-in node catalogue.
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "runtime/exit_codes.hpp"
#include "tests/cli/command.hpp"
#include "tests/json_file.hpp"
#include "tests/test_support.hpp"

using namespace gslift;
using gslift::test::run_command;
namespace fs = std::filesystem;

namespace {
const std::string kBinary = GSLIFT_BINARY;
}

TEST_CASE("the help flags list the commands and exit codes, globally and per command", "[cli]") {
  for (const char* flag : {" --help", " -h"}) {
    const auto r = run_command(kBinary + flag);
    CHECK(r.code == exit_code::kOk);
    for (const char* word : {"run", "validate", "nodes", "batch", "130", "invalid graph"})
      CHECK(r.output.find(word) != std::string::npos);
  }
  for (const char* cmd : {"run", "validate", "nodes", "batch"}) {
    const auto r = run_command(kBinary + " " + cmd + " --help");
    INFO(cmd);
    CHECK(r.code == exit_code::kOk);
    CHECK(r.output.find(std::string("usage: gslift ") + cmd) != std::string::npos);
    CHECK(r.output.find("exit codes:") != std::string::npos);
  }
  // No command at all is a usage error that still shows the help.
  const auto none = run_command(kBinary);
  CHECK(none.code == exit_code::kUsage);
  CHECK(none.output.find("commands:") != std::string::npos);
}

TEST_CASE("synth takes --threads and --log-level like every other command", "[cli]") {
  const fs::path dir = test::scratch_dir("cli_synth_common");
  const std::string small = " --width 96 --height 72 --views 4";
  const auto one = run_command(kBinary + " synth --out '" + (dir / "one").string() + "'" + small +
                               " --threads 1 --log-level warn");
  INFO(one.output);
  CHECK(one.code == exit_code::kOk);
  const auto two =
      run_command(kBinary + " synth --threads=2 --out '" + (dir / "two").string() + "'" + small);
  CHECK(two.code == exit_code::kOk);
  // The same capture at any thread count.
  CHECK(run_command("diff -r '" + (dir / "one").string() + "' '" + (dir / "two").string() + "'")
            .code == 0);
  CHECK(run_command(kBinary + " synth --out x --threads -1").code == exit_code::kUsage);
  CHECK(run_command(kBinary + " synth --out x --threads 5000").code == exit_code::kUsage);
  CHECK(run_command(kBinary + " synth --out x --threads").code == exit_code::kUsage);
  const auto level = run_command(kBinary + " synth --out x --log-level loud");
  CHECK(level.code == exit_code::kUsage);
  CHECK(level.output.find("unknown --log-level 'loud'") != std::string::npos);
  const auto depth_kind = run_command(kBinary + " synth --out x --rig-depth raw");
  CHECK(depth_kind.code == exit_code::kUsage);
  CHECK(depth_kind.output.find("--rig-depth is sensor or registered") != std::string::npos);
  const auto depth_layout = run_command(kBinary + " synth --out x --rig-depth registered");
  CHECK(depth_layout.code == exit_code::kUsage);
  CHECK(depth_layout.output.find("--rig-depth needs --layout rig") != std::string::npos);
  const auto help = run_command(kBinary + " synth --help");
  CHECK(help.code == exit_code::kOk);
  CHECK(help.output.find("--threads N") != std::string::npos);
  CHECK(help.output.find("--log-level L") != std::string::npos);
}

TEST_CASE("the version flag prints the project and git versions", "[cli]") {
  const auto r = run_command(kBinary + " --version");
  CHECK(r.code == exit_code::kOk);
  CHECK(r.output.rfind("gslift 0.1.0 (", 0) == 0);
}

TEST_CASE("an unknown command is a usage error with a suggestion", "[cli]") {
  const auto r = run_command(kBinary + " rnu graphs/demo.yaml");
  CHECK(r.code == exit_code::kUsage);
  CHECK(r.output.find("unknown command 'rnu' (did you mean 'run'?)") != std::string::npos);
}

TEST_CASE("validate reports an invalid graph with file:line and exit code 3", "[cli]") {
  const fs::path dir = test::scratch_dir("cli_validate_invalid");
  const fs::path graph = dir / "bad.yaml";
  std::ofstream(graph) << "graph: bad\nnodes:\n  x: {type: no.such_type}\n";
  const auto r = run_command(kBinary + " validate '" + graph.string() + "'");
  INFO(r.output);
  CHECK(r.code == exit_code::kInvalidGraph);
  CHECK(r.output.find(graph.string() + ":3:") != std::string::npos);
  CHECK(r.output.find("no.such_type") != std::string::npos);
}

TEST_CASE("nodes lists the catalogue and documents every listed type", "[cli]") {
  const auto list = run_command(kBinary + " nodes");
  REQUIRE(list.code == exit_code::kOk);
  std::istringstream lines(list.output);
  std::string line;
  int types = 0;
  while (std::getline(lines, line)) {
    const std::string type = line.substr(0, line.find(' '));
    const auto page = run_command(kBinary + " nodes " + type);
    INFO(type);
    CHECK(page.code == exit_code::kOk);
    CHECK(page.output.rfind(type + ": ", 0) == 0);
    CHECK(page.output.find("\ninputs:\n") != std::string::npos);
    CHECK(page.output.find("\nparams:\n") != std::string::npos);
    ++types;
  }
  WARN(types << " node types registered");
}

TEST_CASE("every graph shipped in graphs/ validates against the built-in catalogue",
          "[cli][long]") {
  int graphs = 0;
  for (const auto& e : fs::recursive_directory_iterator(fs::path(GSLIFT_SOURCE_DIR) / "graphs")) {
    if (e.path().extension() != ".yaml") continue;
    // graphs/ also holds data files that graphs reference (vocabularies): a graph file has a
    // top-level `nodes:` or `extends:`.
    std::ifstream in(e.path());
    const std::string text = "\n" + std::string((std::istreambuf_iterator<char>(in)), {});
    if (text.find("\nnodes:") == std::string::npos && text.find("\nextends:") == std::string::npos)
      continue;
    // With --input the capture is opened and checked against what every node needs of it: the
    // embedded OR holds everything a shipped graph reads (images, depth, VLM replies, SAM masks,
    // ground truth, held-out views) but the object masks of the DTU and lego graphs, which are
    // checked on their own scenes (skipped where ../shared/data is absent).
    // Production graphs whose graph params have no default get what a user gives.
    const std::string name = e.path().filename().string();
    const std::string scene = name.find("lego") != std::string::npos  ? "nerf_synthetic_lego_subset"
                              : name.find("dtu") != std::string::npos ? "dtu_scan24"
                                                                      : "";
    if (!scene.empty() && !fs::exists(test::shared_data(scene))) {
      WARN("SKIPPED " << name << ": " << test::shared_data(scene).string() << " is absent");
      continue;
    }
    const std::string input =
        scene.empty() ? std::string("embedded:or") : "'" + test::shared_data(scene).string() + "'";
    const bool production = e.path().parent_path().filename() == "production";
    const std::string sets = !production                      ? ""
                             : name == "saga.yaml"            ? " --set prompts=clicks.json"
                             : name == "detector_fusion.yaml" ? " --set 'classes=[patient]'"
                                                              : "";
    const auto r = run_command(kBinary + " validate '" + e.path().string() + "' --input " + input +
                               " --log-level warn" + sets);
    INFO(e.path().string() << "\n" << r.output);
    CHECK(r.code == exit_code::kOk);
    ++graphs;
  }
  CHECK(graphs >= 1);
}

TEST_CASE("the demo graph runs on a real capture and records it", "[cli]") {
  GSLIFT_REQUIRE_SHARED_DATA("replica_nice_slam_rgbd/room0");
  const fs::path out = test::scratch_dir("cli_demo_replica");
  const auto r =
      run_command(kBinary + " run '" + GSLIFT_SOURCE_DIR + "/graphs/demo.yaml' --input '" +
                  test::shared_data("replica_nice_slam_rgbd/room0").string() + "' --out '" +
                  out.string() + "' --log-level warn");
  INFO(r.output);
  REQUIRE(r.code == exit_code::kOk);
  CHECK(r.output.find("results: " + out.string() + " (run.json)") != std::string::npos);
  std::ifstream in(out / "run.json");
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  CHECK(text.find("\"status\": \"ok\"") != std::string::npos);
  CHECK(text.find("\"type\": \"ingest.capture\"") != std::string::npos);
}

TEST_CASE("the demo graph runs with no data: the embedded operating room", "[cli]") {
  const fs::path out = test::scratch_dir("cli_demo_embedded");
  const auto r = run_command(kBinary + " run '" + GSLIFT_SOURCE_DIR + "/graphs/demo.yaml' --out '" +
                             out.string() + "' --log-level warn");
  INFO(r.output);
  REQUIRE(r.code == exit_code::kOk);
  std::ifstream in(out / "run.json");
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  CHECK(text.find("\"input\": \"embedded:or\"") != std::string::npos);
  CHECK(text.find("\"status\": \"ok\"") != std::string::npos);
}

TEST_CASE("validate --input refuses a capture that is not there or is no capture",
          "[cli][preflight]") {
  const std::string graph = std::string(GSLIFT_SOURCE_DIR) + "/graphs/langor.yaml";
  const auto missing =
      run_command(kBinary + " validate '" + graph + "' --input /nonexistent/capture");
  INFO(missing.output);
  CHECK(missing.code == exit_code::kBadInput);
  CHECK(missing.output.find("node 'capture' (ingest.capture) cannot open its capture: "
                            "/nonexistent/capture: no such capture folder") != std::string::npos);
  const fs::path empty = test::scratch_dir("cli_validate_not_a_capture");
  const auto not_capture =
      run_command(kBinary + " validate '" + graph + "' --input '" + empty.string() + "'");
  INFO(not_capture.output);
  CHECK(not_capture.code == exit_code::kBadInput);
  CHECK(not_capture.output.find(": not a capture; looked for capture.yaml") != std::string::npos);
  // Without --input, validate checks the graph alone, as before.
  CHECK(run_command(kBinary + " validate '" + graph + "'").code == exit_code::kOk);
}

TEST_CASE("LangOR on a capture without VLM replies is refused before any node runs",
          "[cli][preflight]") {
  const fs::path dir = test::scratch_dir("cli_langor_no_vlm");
  const fs::path capture = dir / "capture";
  const auto synth = run_command(kBinary + " synth --out '" + capture.string() +
                                 "' --width 96 --height 72 --views 5 --log-level warn");
  REQUIRE(synth.code == exit_code::kOk);
  fs::remove_all(capture / "vlm");
  const std::string graph = std::string(GSLIFT_SOURCE_DIR) + "/graphs/langor.yaml";
  const std::string expected =
      "node 'vlm' (ingest.vlm) needs VLM grounding replies of capture "
      "'capture': looked for " +
      (capture / "vlm" / "").string() + "<view>/round_0.txt";
  const auto v =
      run_command(kBinary + " validate '" + graph + "' --input '" + capture.string() + "'");
  INFO(v.output);
  CHECK(v.code == exit_code::kBadInput);
  CHECK(v.output.find(expected) != std::string::npos);
  CHECK(v.output.find("vlm.query") != std::string::npos);  // what produces the replies

  const fs::path out = dir / "out";
  const auto r = run_command(kBinary + " run '" + graph + "' --input '" + capture.string() +
                             "' --out '" + out.string() + "' --no-cache --log-level warn");
  INFO(r.output);
  CHECK(r.code == exit_code::kBadInput);
  CHECK(r.output.find(expected) != std::string::npos);
  // One message for the one thing missing: the box masks and everything else are there.
  CHECK(r.output.find("preflight: 1 problem with") != std::string::npos);
  // No node ran: run.json says failed with every node pending, and no node folder was made.
  std::ifstream in(out / "run.json");
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  CHECK(text.find("\"status\": \"failed\"") != std::string::npos);
  CHECK(text.find("\"status\": \"ok\"") == std::string::npos);
  CHECK_FALSE(fs::exists(out / "capture"));
  CHECK_FALSE(fs::exists(out / "recon"));
}

namespace {
std::filesystem::path write_file_text(const std::filesystem::path& file, const std::string& text) {
  std::ofstream(file) << text;
  return file;
}
std::string shell_quoted(const std::filesystem::path& p) {
  return "'" + p.string() + "'";
}
}  // namespace

TEST_CASE("sweep over a capture set runs every combination on each capture and pairs them",
          "[cli]") {
  const fs::path dir = test::scratch_dir("cli_sweep_inputs");
  // Two tiny embedded rooms of 4 and 5 views: ingest's `views` record tells them apart. The
  // grid's two values change no record, so every paired difference is 0 (the arithmetic of the
  // interval is runtime_test's hand-computed case).
  const fs::path graph = write_file_text(dir / "rooms.yaml", R"(graph: rooms
params: {input: ""}
nodes:
  capture: {type: ingest.capture, params: {path: "${input}"}}
)");
  const fs::path set = write_file_text(dir / "rooms.txt", R"(# two rooms
embedded:or?seed=1&views=4&width=64&height=48
embedded:or?seed=2&views=5&width=64&height=48  # a comment
)");
  const fs::path out = dir / "out";
  const auto r = run_command(kBinary + " sweep " + shell_quoted(graph) +
                             " --grid capture.allow_outside_paths=false,true" + " --inputs " +
                             shell_quoted(set) + " --seeds 0-1 --out " + shell_quoted(out));
  INFO(r.output);
  REQUIRE(r.code == exit_code::kOk);
  const nlohmann::json sweep = test::read_json(out / "sweep.json");
  REQUIRE(sweep["runs"].size() == 8);  // 2 values x 2 rooms x 2 seeds
  CHECK(sweep["inputs"].size() == 2);
  for (const auto& run : sweep["runs"]) {
    const bool second = run["input"].get<std::string>().find("seed=2") != std::string::npos;
    CHECK(run["metrics"]["capture.views"] == (second ? 5.0 : 4.0));
  }
  // Rooms are pooled like seeds: 4 runs per value, views averaging 4.5.
  REQUIRE(sweep["summary"].size() == 2);
  CHECK(sweep["summary"][0]["n"] == 4);
  CHECK(sweep["summary"][0]["metrics"]["capture.views"]["mean"] == Approx(4.5));
  CHECK_FALSE(sweep["summary"][0].contains("paired"));
  // The second value against the first, room by room and seed by seed: 4 pairs.
  const nlohmann::json& paired = sweep["summary"][1]["paired"];
  CHECK(paired["against"]["capture.allow_outside_paths"] == "false");
  CHECK(paired["metrics"]["capture.views"]["n"] == 4);
  CHECK(paired["metrics"]["capture.views"]["mean"].get<double>() == 0.0);
  CHECK(paired["metrics"]["capture.views"]["low"].get<double>() == 0.0);
  std::ifstream csv(out / "results.csv");
  std::string header;
  std::getline(csv, header);
  CHECK(header.rfind("run,seed,input,status,error,capture.allow_outside_paths", 0) == 0);

  // A set line naming no capture is refused before any run, with the capture's path.
  const fs::path bad_set =
      write_file_text(dir / "bad.txt", "embedded:or?seed=1&views=4\nno_such_room\n");
  // So is a line whose embedded capture cannot be made, before anything is generated.
  const fs::path two_views = write_file_text(dir / "two.txt", "embedded:or?seed=1&views=2\n");
  const auto two = run_command(kBinary + " sweep " + shell_quoted(graph) + " --inputs " +
                               shell_quoted(two_views) + " --out " + shell_quoted(dir / "two"));
  CHECK(two.code == exit_code::kBadInput);
  CHECK(two.output.find("views must be 4..8, got 2") != std::string::npos);
  const auto bad = run_command(kBinary + " sweep " + shell_quoted(graph) + " --inputs " +
                               shell_quoted(bad_set) + " --out " + shell_quoted(dir / "bad"));
  CHECK(bad.code == exit_code::kBadInput);
  CHECK(bad.output.find("no_such_room") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "bad" / "runs"));
  // An empty set and --input with --inputs are errors before anything runs.
  const fs::path empty_set = write_file_text(dir / "empty.txt", "# nothing\n");
  CHECK(run_command(kBinary + " sweep " + shell_quoted(graph) + " --inputs " +
                    shell_quoted(empty_set) + " --out " + shell_quoted(dir / "empty"))
            .code == exit_code::kBadInput);
  CHECK(run_command(kBinary + " sweep " + shell_quoted(graph) + " --inputs " + shell_quoted(set) +
                    " --input x --out " + shell_quoted(dir / "both"))
            .code == exit_code::kUsage);
}

TEST_CASE("production SAGA and detector fusion validate on a capture without ground truth",
          "[cli][preflight][production]") {
  const fs::path dir = test::scratch_dir("cli_production_graphs");
  const fs::path capture = dir / "capture";
  REQUIRE(run_command(kBinary + " synth --out '" + capture.string() +
                      "' --width 96 --height 72 --views 5 --log-level warn")
              .code == exit_code::kOk);
  fs::remove_all(capture / "gt");  // a capture of one's own has no ground truth
  const std::string graphs = std::string(GSLIFT_SOURCE_DIR) + "/graphs/";
  const auto validate = [&](const std::string& graph, const std::string& sets) {
    return run_command(kBinary + " validate '" + graphs + graph + "' --input '" + capture.string() +
                       "'" + sets);
  };
  // The evaluated graphs need ground truth: refused, naming it.
  const auto saga = validate("saga.yaml", "");
  INFO(saga.output);
  CHECK(saga.code == exit_code::kBadInput);
  CHECK(saga.output.find("node 'truth' (masks.ground_truth) needs ground-truth instance") !=
        std::string::npos);
  const auto fusion = validate("detector_fusion.yaml", "");
  INFO(fusion.output);
  CHECK(fusion.code == exit_code::kBadInput);
  CHECK(fusion.output.find("node 'source3d' (fusion.render_semantics) needs ground-truth class "
                           "names") != std::string::npos);

  // Their production forms need what only the user can give: a prompt file, a vocabulary.
  const auto no_prompts = validate("production/saga.yaml", "");
  INFO(no_prompts.output);
  CHECK(no_prompts.code == exit_code::kInvalidGraph);
  CHECK(no_prompts.output.find("graph param 'prompts' has no value") != std::string::npos);
  CHECK(no_prompts.output.find("--set prompts=VALUE") != std::string::npos);
  const fs::path prompts = dir / "clicks.json";
  std::ofstream(prompts) << R"([{"name": "table", "view": "cam_00", "positive": [[48, 40]]}])";
  const auto prompted =
      validate("production/saga.yaml", " --set prompts='" + prompts.string() + "'");
  INFO(prompted.output);
  CHECK(prompted.code == exit_code::kOk);

  const auto no_classes = validate("production/detector_fusion.yaml", "");
  INFO(no_classes.output);
  CHECK(no_classes.code == exit_code::kInvalidGraph);
  CHECK(no_classes.output.find("graph param 'classes' has no value") != std::string::npos);
  const auto classes =
      validate("production/detector_fusion.yaml", " --set 'classes=[operating table, surgeon]'");
  INFO(classes.output);
  CHECK(classes.code == exit_code::kOk);
}

TEST_CASE("sweep --dry-run validates every combination and capture, runs and writes nothing",
          "[cli]") {
  const fs::path dir = test::scratch_dir("cli_sweep_dry_run");
  const fs::path graph = write_file_text(dir / "rooms.yaml", R"(graph: rooms
params: {input: ""}
nodes:
  capture: {type: ingest.capture, params: {path: "${input}"}}
)");
  const fs::path set = write_file_text(dir / "rooms.txt",
                                       "embedded:or?seed=1&views=4&width=64&height=48\n"
                                       "embedded:or?seed=2&views=5&width=64&height=48\n");
  // 2 values x 2 rooms x 3 seeds, no --out needed; nothing is written.
  const auto ok = run_command(kBinary + " sweep " + shell_quoted(graph) +
                              " --grid capture.allow_outside_paths=false,true --inputs " +
                              shell_quoted(set) + " --seeds 0-2 --dry-run");
  INFO(ok.output);
  CHECK(ok.code == exit_code::kOk);
  CHECK(ok.output.find("12 runs of") != std::string::npos);
  CHECK(ok.output.find("(grid combinations 2, seeds 3, captures 2)") != std::string::npos);
  const auto with_out =
      run_command(kBinary + " sweep " + shell_quoted(graph) + " --inputs " + shell_quoted(set) +
                  " --dry-run --out " + shell_quoted(dir / "out"));
  CHECK(with_out.code == exit_code::kOk);
  CHECK_FALSE(fs::exists(dir / "out"));
  // What a real sweep refuses before its first run, a dry run refuses the same way.
  const auto misspelt = run_command(kBinary + " sweep " + shell_quoted(graph) +
                                    " --grid capture.allow_outside_pahts=false --inputs " +
                                    shell_quoted(set) + " --dry-run");
  CHECK(misspelt.code == exit_code::kInvalidGraph);
  CHECK(misspelt.output.find("allow_outside_pahts") != std::string::npos);
  const fs::path two_views = write_file_text(dir / "two.txt", "embedded:or?seed=1&views=2\n");
  const auto two = run_command(kBinary + " sweep " + shell_quoted(graph) + " --inputs " +
                               shell_quoted(two_views) + " --dry-run");
  CHECK(two.code == exit_code::kBadInput);
  CHECK(two.output.find("views must be 4..8, got 2") != std::string::npos);
  // Without --dry-run, --out stays required.
  CHECK(run_command(kBinary + " sweep " + shell_quoted(graph) + " --inputs " + shell_quoted(set))
            .code == exit_code::kUsage);
  // A warning every combination shares is printed once, not once per combination.
  const fs::path partly = write_file_text(dir / "partly.yaml", R"(graph: partly
params: {input: ""}
nodes:
  capture: {type: ingest.capture, params: {path: "${input}"}}
  recon: {type: splat.reconstruct, in: {capture: capture.capture}}
  render: {type: splat.render, in: {model: recon.model, capture: capture.capture}}
)");
  // With --seeds and without (the graph's own seed is read from a first load).
  for (const std::string seeds : {" --seeds 0-1", ""}) {
    const auto warned = run_command(kBinary + " sweep " + shell_quoted(partly) + " --inputs " +
                                    shell_quoted(set) + seeds + " --dry-run");
    INFO(seeds << ": " << warned.output);
    CHECK(warned.code == exit_code::kOk);
    const std::string warning = "warning[unused-output]";
    const size_t first = warned.output.find(warning);
    CHECK(first != std::string::npos);
    CHECK(warned.output.find(warning, first + 1) == std::string::npos);
  }
}
