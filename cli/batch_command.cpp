// `gslift batch MANIFEST GRAPH` / `--discover DIR GRAPH`: one `gslift run` child per capture of
// this shard, each into its own folder (runtime/batch.hpp), and the summary table.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "cli/child_run.hpp"
#include "cli/graph_file.hpp"
#include "cli/output_folder.hpp"
#include "cli/runtime_commands.hpp"
#include "runtime/batch.hpp"
#include "runtime/child_process.hpp"
#include "runtime/exit_codes.hpp"
#include "runtime/signals.hpp"

namespace gslift {

namespace fs = std::filesystem;

namespace {

const CommandHelp& batch_help() {
  static const CommandHelp help{
      "usage: gslift batch MANIFEST GRAPH --out DIR [--shard I/N] [--set NODE.PARAM=VALUE]...\n"
      "                    [--threads N] [--seed S] [--log-level L]\n"
      "       gslift batch --discover DIR GRAPH --out OUT [options as above]\n\n"
      "MANIFEST lists one capture path per line ('#' comments; relative paths are relative to\n"
      "the manifest). Each capture's results go to DIR/<capture name>/, written under a\n"
      "temporary name and renamed when finished, with a _DONE marker: a rerun skips finished\n"
      "captures. A failed capture gets _FAILED.json and the others go on. A summary table is\n"
      "printed and written to DIR/_summary.json (with shards, each writes _summary-IofN.json and\n"
      "_summary.json merges those present). docs/batch-cluster.md: Slurm, Kubernetes, nightly.\n\n",
      {kOutOption.described("results root (required)"),
       {"discover", "DIR",
        "the captures are DIR's subfolders without OUT/<name>/_DONE\n"
        "(names starting with '.' or '_' are left out)"},
       {"shard", "I/N",
        "take the captures whose index % N == I; without it, from\n"
        "SLURM_ARRAY_TASK_ID/_MIN/_COUNT or JOB_COMPLETION_INDEX"},
       {"shard-count", "N",
        "the shard count with JOB_COMPLETION_INDEX (Kubernetes Indexed\n"
        "Job completions; or set GSLIFT_SHARD_COUNT)"},
       kSetOption,
       kThreadsOption.described(
           "worker threads per capture, 0 = all cores (default 0, at most 1024)"),
       kSeedOption.described("run seed (graph var ${seed}); the same for every capture"),
       kLogLevelOption,
       kCacheOptions[0],
       kCacheOptions[1],
       kCacheOptions[2],
       kHelpOption},
      ""};
  return help;
}

int cmd_batch(int argc, char** argv, const Registry& registry) {
  const Args args = parse_args(argc, argv, 2, batch_help().options);
  if (args.flags.count("help")) return print_command_help(batch_help()), 0;
  const bool discover = args.has("discover");
  if (args.positional.size() != (discover ? 1u : 2u))
    throw UsageError(discover ? "batch --discover DIR expects GRAPH only"
                              : "batch expects MANIFEST and GRAPH");
  if (!args.has("out")) throw UsageError("batch needs --out DIR");
  set_up_logging(args);
  Shard shard;
  try {
    std::optional<int> shard_count;
    if (args.has("shard-count"))
      shard_count = static_cast<int>(parse_integer("shard-count", args.last("shard-count"), 1,
                                                   std::numeric_limits<int>::max()));
    if (args.has("shard")) {
      shard = parse_shard(args.last("shard"));
    } else if (const auto from_env = shard_from_environment(
                   [](const std::string& name) -> std::optional<std::string> {
                     const char* v = std::getenv(name.c_str());
                     return v ? std::optional<std::string>(v) : std::nullopt;
                   },
                   shard_count)) {
      shard = from_env->shard;
      spdlog::info("shard {}/{} from {}", shard.index, shard.count, from_env->source);
    }
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  parse_threads(args);
  check_output_folder(args.last("out"));
  command_line_cache(args);  // a bad --cache-dir is one error here, not one per capture
  const auto manifest = discover ? discover_captures(args.last("discover"), args.last("out"))
                                 : read_manifest(args.positional[0]);
  const std::string graph_file = args.positional[discover ? 0 : 1];
  if (discover)
    spdlog::info("discovered {} capture(s) without a result under {}", manifest.size(),
                 args.last("discover"));
  // Validate once up front (with the shard's first capture as ${input}) so that a broken graph
  // is one error, not one failure per capture.
  for (const auto& e : manifest) {
    if (!shard.takes(e.index)) continue;
    LoadOptions lopt = load_options(args);
    lopt.vars["input"] = e.path;
    if (!load_checked(graph_file, registry, lopt)) return exit_code::kInvalidGraph;
    break;
  }
  install_interrupt_handlers();
  const auto run_capture = [&](const ManifestEntry& e, const fs::path& out) {
    // The capture's log (its gslift.log) at the batch's level: a nightly log keeps each
    // capture's progress, as when the batch ran them in its own process.
    std::vector<std::string> child =
        child_run_command(args, graph_file, out, args.last("log-level", "info"));
    child.insert(child.end(), {"--input", e.path});
    if (args.has("seed")) child.insert(child.end(), {"--seed", args.last("seed")});
    for (const auto& s : args.all("set")) child.insert(child.end(), {"--set", s});
    const fs::path log = out / "gslift.log";
    return child_run_result(run_child_process(child, log.string(), &interrupt_flag()), out, log);
  };
  const BatchSummary summary =
      run_batch(manifest, args.last("out"), shard, run_capture, &interrupt_flag());
  std::printf("%s", summary.table().c_str());
  if (summary.cannot_write) return exit_code::kCannotWrite;
  if (summary.interrupted) return exit_code::kInterrupted;
  return summary.count(CaptureStatus::Failed) ? exit_code::kBatchPartial : exit_code::kOk;
}

}  // namespace

Command batch_command() {
  return {"batch", "run a graph over many captures", cmd_batch};
}

}  // namespace gslift
