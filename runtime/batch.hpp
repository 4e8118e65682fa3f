// `gslift batch`: one graph over many captures. One graph instance per capture (the executor),
// with this layer above it: a manifest of inputs, one output folder per capture written under a
// temporary name and renamed when finished, a _DONE marker so a rerun skips finished captures,
// --shard i/n so job arrays split the manifest, and a summary at the end. A failed capture is
// recorded (_FAILED.json) and the others go on.
#pragma once

#include <atomic>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "runtime/executor.hpp"

namespace gslift {

struct ManifestEntry {
  std::string path;  // capture path, relative ones resolved against the manifest's folder
  std::string name;  // output folder name: the path's last component, [A-Za-z0-9._-] kept
  int line = 0;      // 1-based line in the manifest
  size_t index = 0;  // 0-based position among the manifest's captures (what --shard splits)
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

enum class CaptureStatus { Done, Skipped, Failed, Interrupted };
// "done", "skipped" (finished by an earlier run), "failed", "interrupted"
const char* to_string(CaptureStatus s);

struct CaptureOutcome {
  std::string name;
  std::string path;
  CaptureStatus status = CaptureStatus::Done;
  double seconds = 0;
  std::string error;  // RunError::str() or the exception text, when failed
};

struct BatchSummary {
  std::vector<CaptureOutcome> captures;  // this shard's captures, manifest order
  bool interrupted = false;              // stopped early; later captures are absent
  int count(CaptureStatus s) const;
  nlohmann::json json() const;
  // A fixed-width table, one row per capture, then the totals.
  std::string table() const;
};

// Runs one capture with its outputs under out_dir (a temporary folder); may throw (an invalid
// graph for this input, ...), which counts as that capture's failure.
using CaptureRunner =
    std::function<RunResult(const ManifestEntry& capture, const std::filesystem::path& out_dir)>;

// Runs the shard's captures one after the other into out_root/<name>/. Stops after the current
// capture when *cancel becomes true (its temporary folder is removed). Writes the summary to
// out_root/_summary.json (_summary-<i>of<n>.json with several shards) and returns it.
BatchSummary run_batch(const std::vector<ManifestEntry>& manifest,
                       const std::filesystem::path& out_root, Shard shard,
                       const CaptureRunner& run_capture, const std::atomic<bool>* cancel = nullptr);

}  // namespace gslift
