// `gslift sweep GRAPH --grid ...`: one `gslift run` child per grid point and seed, each validated
// before the first runs; sweep.json, results.csv and summary.csv rewritten after every run.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <sys/wait.h>

#include <spdlog/spdlog.h>

#include "base/atomic_file.hpp"
#include "base/errors.hpp"
#include "base/input_file.hpp"
#include "base/json_read.hpp"
#include "cli/child_run.hpp"
#include "cli/graph_file.hpp"
#include "cli/output_folder.hpp"
#include "cli/runtime_commands.hpp"
#include "runtime/batch.hpp"
#include "runtime/child_process.hpp"
#include "runtime/exit_codes.hpp"
#include "runtime/preflight.hpp"
#include "runtime/run_record.hpp"
#include "runtime/signals.hpp"
#include "runtime/sweep.hpp"

namespace gslift {

namespace fs = std::filesystem;

namespace {

const CommandHelp& sweep_help() {
  static const CommandHelp help{
      "usage: gslift sweep GRAPH [--grid NODE.PARAM=V1,V2,...]... [--seeds 0-4]\n"
      "                    --out DIR [--input PATH | --inputs SET] [--set NODE.PARAM=VALUE]...\n"
      "                    [--threads N] [--dry-run]\n"
      "                    [--log-level L] [--cache-dir DIR] [--cache-size GB] [--no-cache]\n\n"
      "Runs GRAPH once per combination of the --grid values (the cartesian product), capture of\n"
      "--inputs and seed, each as a `gslift run` of its own in DIR/runs/NNNN/ (its output in\n"
      "gslift.log there)\n"
      "through the stage cache (a changed downstream param reuses everything upstream). Every\n"
      "combination is validated before the first run. DIR/sweep.json, DIR/results.csv (a row\n"
      "per run: params, seed, status, error, time, peak memory, every numeric record as\n"
      "node.key, wall time per node) and DIR/summary.csv (mean and std over seeds and\n"
      "captures) are rewritten after every run, so an interrupted sweep keeps what finished. A\n"
      "failed run is a row with its error; the sweep goes on. With two or more combinations,\n"
      "each is compared with the first capture by capture and seed: the mean difference and\n"
      "its 95% interval (sweep.json's paired, and the table's last lines). gslift report DIR\n"
      "draws it. --dry-run validates every combination (and each capture of --inputs) and\n"
      "prints the plan without running anything (a spec's check; --out is then not needed).\n\n",
      {{"grid", "NODE.PARAM=V,...",
        "the values of one param (repeatable); commas inside [] or\n"
        "quotes belong to a value; NODE.type=A,B swaps stages"},
       {"seeds", "LIST", "0-4, 0,2,7 or 3 (default: the graph's seed)"},
       kOutOption.described("sweep folder (required)"),
       kInputOption.described("the capture (graph var ${input})"),
       {"inputs", "SET",
        "a set of captures, one per line as a batch manifest\n"
        "(bench/sets/or_test.txt): every combination runs on each"},
       kSetOption.described("a param fixed for every run (repeatable)\n"
                            "({seed} in --input, --set and --grid values is the run's seed:\n"
                            "--input 'embedded:or?seed={seed}' varies the capture too)"),
       kThreadsOption.described("worker threads per run, 0 = all cores (default 0, at most 1024)"),
       kLogLevelOption,
       kCacheOptions[0].described("stage cache folder (as gslift run)"),
       kCacheOptions[1].described("cap of the cache folder (default 10, 0 = no cap)"),
       kCacheOptions[2].described("every run runs every node"),
       {"dry-run", "", "validate every combination and print the plan; run nothing"},
       kHelpOption},
      "\nExit code 6 when some runs failed (the table has them), 130 when interrupted.\n"};
  return help;
}

int cmd_sweep(int argc, char** argv, const Registry& registry) {
  const Args args = parse_args(argc, argv, 2, sweep_help().options);
  if (args.flags.count("help")) return print_command_help(sweep_help()), 0;
  if (args.positional.size() != 1) throw UsageError("sweep expects one GRAPH file");
  const bool dry_run = args.flags.count("dry-run") != 0;
  if (!args.has("out") && !dry_run) throw UsageError("sweep needs --out DIR");
  // Seeds alone are a sweep too: the graph as it is, once per seed (a mean over rooms).
  if (!args.has("grid") && !args.has("seeds") && !args.has("inputs"))
    throw UsageError("sweep needs a --grid NODE.PARAM=V1,V2, --seeds LIST or --inputs SET");
  if (args.has("input") && args.has("inputs"))
    throw UsageError("sweep takes --input PATH or --inputs SET, not both");
  set_up_logging(args);
  const fs::path out = args.last("out");
  if (!dry_run) check_output_folder(out);
  const std::string graph_file = args.positional[0];
  std::vector<GridAxis> axes;
  std::vector<uint64_t> seeds;
  try {
    for (const auto& g : args.all("grid")) axes.push_back(parse_grid(g));
    if (args.has("seeds")) seeds = parse_seeds(args.last("seeds"));
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  parse_threads(args);  // a bad --threads is one usage error, before the first run
  std::vector<std::string> inputs;
  if (args.has("inputs")) {
    for (const auto& e : read_manifest(args.last("inputs"))) inputs.push_back(e.path);
    if (inputs.empty())
      throw InputError(args.last("inputs") + ": the capture set lists no capture");
  }
  // Every combination is validated up front: a misspelt grid param is one error, not N failed
  // runs.
  // "{seed}" in --input, --set and --grid values is the run's seed: --input
  // 'embedded:or?seed={seed}' gives every seed a capture of its own.
  const auto with_seed = [](std::string v, uint64_t seed) {
    for (size_t at; (at = v.find("{seed}")) != std::string::npos;)
      v.replace(at, 6, std::to_string(seed));
    return v;
  };
  const auto input_of = [&](const SweepPoint& p) {
    return with_seed(p.input.empty() ? args.last("input") : p.input, p.seed);
  };
  const auto combination_options = [&](const SweepPoint& p) {
    LoadOptions lopt = load_options(args);
    for (auto& set : sweep_point_sets(p)) lopt.sets.push_back(std::move(set));
    for (auto& set : lopt.sets) set = with_seed(set, p.seed);
    if (args.has("input") || !p.input.empty()) lopt.vars["input"] = input_of(p);
    return lopt;
  };
  std::set<std::string> printed;  // each warning once, not once per combination
  if (seeds.empty()) {
    const auto graph = load_checked(graph_file, registry, load_options(args), &printed);
    if (!graph) return exit_code::kInvalidGraph;
    seeds = {run_seed(*graph)};
  }
  std::vector<SweepPoint> points;
  try {
    points = inputs.empty() ? sweep_points(axes, seeds) : sweep_points(axes, seeds, inputs);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  for (const auto& p : points) {
    if (p.seed != seeds.front()) continue;
    const auto graph = load_checked(graph_file, registry, combination_options(p), &printed);
    if (!graph) return exit_code::kInvalidGraph;
    // Each capture of a set is checked as `gslift validate --input` would, before the first run:
    // a misspelt line of the set is one error now, not a failed room an hour in.
    if (!p.input.empty()) check_preflight(*graph, registry);
  }
  if (dry_run) {
    // The plan a spec would run (bench/*/ tables check themselves this way): every combination
    // passed validation above; nothing ran and nothing was written.
    std::printf(
        "sweep --dry-run: %zu runs of %s (grid combinations %zu, seeds %zu, captures %zu), "
        "every combination valid\n",
        points.size(), graph_file.c_str(),
        points.size() / seeds.size() / std::max<size_t>(inputs.size(), 1), seeds.size(),
        std::max<size_t>(inputs.size(), 1));
    return exit_code::kOk;
  }

  install_interrupt_handlers();
  std::vector<SweepRun> runs;
  std::vector<std::string> headline;
  nlohmann::json table;
  spdlog::info("sweep: {} runs of {} -> {}", points.size(), graph_file, out.string());
  for (size_t i = 0; i < points.size() && !interrupt_flag().load(); ++i) {
    // Room for any size_t: g++ warned that 16 bytes could truncate "%04zu" past 10^15 runs.
    char name[24];
    std::snprintf(name, sizeof name, "%04zu", i);
    SweepRun run;
    run.dir = (fs::path("runs") / name).generic_string();
    run.point = points[i];
    const fs::path dir = out / run.dir;
    std::vector<std::string> child = child_run_command(args, graph_file, dir, "warn");
    child.insert(child.end(), {"--seed", std::to_string(run.point.seed)});
    if (args.has("input") || !run.point.input.empty())
      child.insert(child.end(), {"--input", input_of(run.point)});
    for (const auto& s : combination_options(run.point).sets)
      child.insert(child.end(), {"--set", s});
    std::string label;
    for (const auto& [param, value] : run.point.params) label += param + "=" + value + " ";
    if (!run.point.input.empty()) label += run.point.input + " ";
    spdlog::info("sweep {}/{}: {}seed {}", i + 1, points.size(), label, run.point.seed);
    fs::create_directories(dir);
    const ChildRun r = run_child_process(child, (dir / "gslift.log").string(), &interrupt_flag());
    try {
      const nlohmann::json record = parse_json(read_input_file(dir / "run.json", "run.json"));
      run = sweep_run_from_record(record, run);
      if (headline.empty() && run.status == "ok")
        for (const auto& [key, value] : headline_metrics(record)) headline.push_back(key);
    } catch (const std::exception& e) {
      // The child died before writing its record (a crash, or a kill): the row says how.
      // Its own peak memory is unknown: wait4's includes this process's (child_process.hpp).
      run.status = "failed";
      run.total_s = r.wall_s;
      run.peak_rss_mb = 0;
      run.error =
          "gslift run " + child_exit_text(r) +
          (WIFSIGNALED(r.status) ? std::string()
                                 : " without a readable run.json (" + std::string(e.what()) + ")");
    }
    if (run.status != "ok") spdlog::warn("sweep {}: {}: {}", run.dir, run.status, run.error);
    runs.push_back(run);
    table = sweep_json(graph_file, axes, seeds, runs, inputs);
    table["headline"] = headline;
    write_file_atomically(out / "sweep.json", json_text(table));
    write_file_atomically(out / "results.csv", sweep_runs_csv(axes, runs));
    write_file_atomically(out / "summary.csv", sweep_summary_csv(axes, table));
  }
  std::printf("%s", sweep_table(axes, table, headline).c_str());
  std::printf("sweep: %zu of %zu runs\nresults: %s\n", runs.size(), points.size(),
              results_line(out).c_str());
  if (interrupt_flag().load()) return exit_code::kInterrupted;
  for (const auto& r : runs)
    if (r.status != "ok") return exit_code::kBatchPartial;
  return exit_code::kOk;
}

}  // namespace

Command sweep_command() {
  return {"sweep", "run a graph over a grid of params and seeds", cmd_sweep};
}

}  // namespace gslift
