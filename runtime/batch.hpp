// `gslift batch`: one graph over many captures. One graph instance per capture (the executor),
// with this layer above it: a manifest of inputs, one output folder per capture written under a
// temporary name and renamed when finished, a _DONE marker so a rerun skips finished captures,
// --shard i/n so job arrays split the manifest, and a summary at the end. A failed capture is
// recorded (_FAILED.json) and the others go on.
#pragma once

#include <atomic>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "runtime/executor.hpp"

namespace gslift {

struct ManifestEntry {
  std::string path;  // capture path, relative ones resolved against the manifest's folder
  std::string name;  // output folder name: the path's last component, [A-Za-z0-9._-] kept
  int line = 0;      // 1-based line in the manifest
  // What --shard splits: the 0-based position among a manifest's captures; for a discovered
  // capture a hash of its name, so that its shard does not depend on which other captures exist.
  size_t index = 0;
};

// Reads a manifest: one capture path per line; blank lines and lines starting with '#' are
// skipped, as is anything after " #". Throws InputError (naming file and line) when the file is
// unreadable or two captures map to the same output name.
std::vector<ManifestEntry> read_manifest(const std::filesystem::path& manifest);

// --shard i/n: this process takes the captures with index % count == index.
struct Shard {
  int index = 0;
  int count = 1;
  bool takes(size_t i) const { return static_cast<int>(i % static_cast<size_t>(count)) == index; }
};
// Parses "i/n" with 0 <= i < n; throws std::invalid_argument saying what is wrong.
Shard parse_shard(const std::string& text);

// The shard a scheduler's array task gives this process when --shard is not given:
//   Slurm job arrays: SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN (0 when MIN is unset) of
//     SLURM_ARRAY_TASK_COUNT (the array must be a contiguous range such as 0-3 or 1-4);
//   Kubernetes Indexed Jobs: JOB_COMPLETION_INDEX of count_option, else of GSLIFT_SHARD_COUNT
//     (the Job's `completions`, which Kubernetes does not pass to the pod).
// Slurm wins when both are set; nullopt when neither is (one process takes every capture).
// A malformed or out-of-range value throws std::invalid_argument naming the variable.
// `env` looks a variable up (std::getenv in the command line; a map in tests).
struct ShardFromEnvironment {
  Shard shard;
  std::string source;  // "SLURM_ARRAY_TASK_ID=5 (SLURM_ARRAY_TASK_MIN=1, ...)", for the log
};
using EnvironmentLookup = std::function<std::optional<std::string>(const std::string& name)>;
std::optional<ShardFromEnvironment> shard_from_environment(const EnvironmentLookup& env,
                                                           std::optional<int> count_option);

// `batch --discover DIR`: a capture folder is a direct subfolder of DIR (or a symlink to one)
// whose name starts with neither '.' nor '_' (copy a capture in under a dot-name and rename it
// when complete, so a half-copied capture is never picked up); the graph's ingest decides
// whether it is readable. It has a result when out_root/<name>/_DONE exists: failed captures
// are retried by the next run. Returns those without a result, sorted by name, each with a hash
// of its name as its index; out_root itself is never a capture. Throws InputError when DIR is
// not a readable folder.
std::vector<ManifestEntry> discover_captures(const std::filesystem::path& dir,
                                             const std::filesystem::path& out_root);

enum class CaptureStatus { Done, Skipped, Failed, Interrupted };
// "done", "skipped" (finished by an earlier run), "failed", "interrupted"
const char* to_string(CaptureStatus s);

struct CaptureOutcome {
  std::string name;
  std::string path;
  CaptureStatus status = CaptureStatus::Done;
  double seconds = 0;
  std::string error;  // RunError::str() or the exception text, when failed
  // The headline metrics of its run.json (run_record.hpp), also for a capture an earlier run
  // finished; empty when it has none (no eval node, or failed before them).
  std::vector<std::pair<std::string, double>> metrics;
  bool cannot_write = false;  // failed because results could not be written (disk full, ...)
};

struct BatchSummary {
  std::vector<CaptureOutcome> captures;  // this shard's captures, manifest order
  bool interrupted = false;              // stopped early; later captures are absent
  // Stopped early because a capture's results could not be written (OutputError: disk full,
  // read-only folder): the rest would fail alike. The command line exits kCannotWrite.
  bool cannot_write = false;
  int count(CaptureStatus s) const;
  nlohmann::json json() const;
  // A fixed-width table, one row per capture with its headline metrics (a column per metric any
  // capture has), then the totals.
  std::string table() const;
};

// Runs one capture with its outputs under out_dir (a temporary folder); may throw (an invalid
// graph for this input, ...), which counts as that capture's failure. The command line runs each
// capture as a `gslift run` child process (child_run_result), as `gslift sweep` runs each point,
// so that whatever one capture does to its process is that capture's failure alone.
using CaptureRunner =
    std::function<RunResult(const ManifestEntry& capture, const std::filesystem::path& out_dir)>;

struct ChildRun;
// What a `gslift run` child that ran into run_dir did, as a RunResult: its run.json's status and
// error when it exited after writing one; otherwise (a crash, an abort in a library, the kernel's
// OOM kill, an invalid graph) a failure saying how it ended (child_exit_text) with the last line
// of `log`. An exit of 130 without a record is an interruption, 73 an OutputError.
RunResult child_run_result(const ChildRun& child, const std::filesystem::path& run_dir,
                           const std::filesystem::path& log);

// Runs the shard's captures one after the other into out_root/<name>/. Stops after the current
// capture when *cancel becomes true (its temporary folder is removed), or when it could not be
// written (its temporary folder is removed; when not even the summary can be written, the
// OutputError propagates). Writes the summary to
// out_root/_summary.json and returns it. With several shards each writes
// out_root/_summary-<i>of<n>.json and then, under a lock on out_root/.summary.lock, merges every
// _summary-*of<n>.json there into out_root/_summary.json (rows by name, counts summed, the
// shards merged listed), so whichever shard finishes last leaves the summary of the whole array.
BatchSummary run_batch(const std::vector<ManifestEntry>& manifest,
                       const std::filesystem::path& out_root, Shard shard,
                       const CaptureRunner& run_capture, const std::atomic<bool>* cancel = nullptr);

}  // namespace gslift
