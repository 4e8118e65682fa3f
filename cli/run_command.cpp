// `gslift run GRAPH`: load -> validate -> run -> run.json, with the closing line and the exit code
// the run's outcome maps to.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "base/atomic_file.hpp"
#include "base/utf8.hpp"
#include "cli/graph_file.hpp"
#include "cli/output_folder.hpp"
#include "cli/runtime_commands.hpp"
#include "runtime/exit_codes.hpp"
#include "runtime/progress.hpp"
#include "runtime/signals.hpp"

namespace gslift {

namespace fs = std::filesystem;

namespace {

const CommandHelp& run_help() {
  static const CommandHelp help{
      "usage: gslift run GRAPH [--input PATH] [--set NODE.PARAM=VALUE]... [--out DIR]\n"
      "                        [--threads N] [--seed S] [--log-level L]\n"
      "                        [--cache-dir DIR] [--cache-size GB] [--no-cache]\n\n"
      "Validates GRAPH, runs it and writes every node's outputs under DIR/<node id>/ and the\n"
      "run record DIR/run.json (also when the run fails).\n\n",
      {kInputOption, kSetOption, kOutOption.described("results folder (default out/<graph name>)"),
       kThreadsOption, kSeedOption, kLogLevelOption, kCacheOptions[0], kCacheOptions[1],
       kCacheOptions[2], kHelpOption},
      "\nA node whose type, params, input files, seed and inputs match an earlier run is loaded\n"
      "from the stage cache instead of run (run.json says \"cache\": \"hit\").\n"};
  return help;
}

// "13 nodes, 9 loaded from the cache" for the closing line.
std::string cache_summary(const RunResult& r) {
  int hits = 0;
  for (const auto& n : r.nodes) hits += n.cache == "hit";
  return hits ? " (" + std::to_string(hits) + " of " + std::to_string(r.nodes.size()) +
                    " nodes loaded from the stage cache)"
              : std::string();
}

int exit_code_of(const RunResult& r) {
  if (r.status == RunStatus::Ok) return exit_code::kOk;
  if (r.status == RunStatus::Interrupted) return exit_code::kInterrupted;
  if (r.error && r.error->kind == RunError::Kind::Output) return exit_code::kCannotWrite;
  return r.error && r.error->kind == RunError::Kind::BadInput ? exit_code::kBadInput
                                                              : exit_code::kNodeFailed;
}

int cmd_run(int argc, char** argv, const Registry& registry) {
  const Args args = parse_args(argc, argv, 2, run_help().options);
  if (args.flags.count("help")) return print_command_help(run_help()), 0;
  if (args.positional.size() != 1) throw UsageError("run expects one GRAPH file");
  set_up_logging(args);
  RunOptions opt = command_line_run_options(args);
  const auto graph = load_checked(args.positional[0], registry, load_options(args));
  if (!graph) return exit_code::kInvalidGraph;
  opt.seed = run_seed(*graph);
  opt.out_dir = args.last("out", (fs::path("out") / graph->name).string());
  check_output_folder(opt.out_dir);
  check_results_folder(opt.out_dir);
  const auto cache = command_line_cache(args);
  opt.cache = cache.get();
  std::vector<std::string> node_folders;
  for (const auto& n : graph->nodes) node_folders.push_back(n.id);
  if (const size_t stale = remove_stale_temporaries(opt.out_dir, node_folders))
    spdlog::info("removed {} unfinished file(s) left in {} by a killed run", stale,
                 opt.out_dir.string());
  ConsoleProgress progress(is_terminal(stderr), stderr);
  opt.progress = &progress;
  install_interrupt_handlers();
  spdlog::info("running {} ({} nodes, threads {}, seed {}) -> {}", graph->name, graph->nodes.size(),
               opt.threads ? std::to_string(opt.threads) : std::string("auto"), opt.seed,
               opt.out_dir.string());
  const RunResult result = execute(*graph, registry, opt);
  if (result.error) std::fprintf(stderr, "error: %s\n", terminal_safe(result.error->str()).c_str());
  std::printf("%s in %.2f s%s\nresults: %s\n", to_string(result.status), result.total_s,
              cache_summary(result).c_str(), results_line(opt.out_dir).c_str());
  return exit_code_of(result);
}

}  // namespace

Command run_command() {
  return {"run", "run a graph on one capture", cmd_run};
}

}  // namespace gslift
