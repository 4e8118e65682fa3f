// Runs a validated Graph on a oneTBB flow graph: one continue_node per graph node, an edge per
// producer -> consumer dependency, so independent branches run concurrently. Each node reads its
// inputs from the outputs its producers stored and stores its own; values are shared pointers, so
// fan-out copies nothing. A node that throws cancels the rest of the run; the error names the node,
// its type and its YAML line.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "graph/graph.hpp"
#include "graph/loader.hpp"
#include "runtime/progress.hpp"
#include "runtime/registry.hpp"
#include "runtime/stage_cache.hpp"
#include "runtime/value.hpp"

namespace gslift {

struct RunOptions {
  int threads = 0;    // worker threads; 0 = all cores (tbb::info::default_concurrency)
  uint64_t seed = 0;  // run seed; each node gets node_seed(seed, id) (runtime/node_seed.hpp)
  std::filesystem::path out_dir;  // results root: <out>/<node id>/ and run.json; empty = no files
  std::string run_input;          // --input, visible to nodes as ctx.run_input()
  // Set from outside (SIGINT/SIGTERM) to stop the run; null = never.
  std::atomic<bool>* cancel = nullptr;
  ProgressSink* progress = nullptr;  // null = silent
  // Where nodes' results are looked up and stored (runtime/stage_cache.hpp); null = no cache.
  StageCache* cache = nullptr;
  // Check what the nodes need of the capture before any runs (runtime/preflight.hpp); a run that
  // fails it runs nothing and fails as bad input.
  bool preflight = true;
};

// Running: what run.json says while the run is under way (and after a SIGKILL or power loss).
enum class RunStatus { Ok, Failed, Interrupted, Running };
// "ok", "failed", "interrupted", "running"
const char* to_string(RunStatus s);

// "pending" = never started (an upstream node failed or the run was cancelled first).
enum class NodeStatus { Pending, Ok, Failed, Cancelled };
const char* to_string(NodeStatus s);

// Why a run stopped. BadInput: the node threw InputError; NodeFailed: any other exception or a
// broken contract (a missing output); Cancelled: interrupted from outside (SIGINT).
struct RunError {
  // Output: the node's results could not be written (OutputError: disk full, read-only folder).
  enum class Kind { BadInput, NodeFailed, Cancelled, Output };
  Kind kind = Kind::NodeFailed;
  std::string node;  // node id; empty for a run cancelled before any node failed
  std::string type;  // node type
  SourceLoc loc;     // where the node is declared in the YAML
  std::string message;
  // "graphs/x.yaml:4:3: node 'boxes' (boxes.cluster) failed: <message>"
  std::string str() const;
};
// "bad-input", "node-failed", "cancelled"
const char* to_string(RunError::Kind k);

struct NodeRecord {
  std::string id;
  std::string type;
  NodeStatus status = NodeStatus::Pending;
  double start_s = 0;  // seconds since the run started (0 when never started)
  double end_s = 0;
  // Process peak resident memory (VmHWM) when the node ended: the first node after which it
  // jumps is the one that needed the memory.
  int64_t peak_rss_kb = 0;
  std::map<std::string, RecordValue> records;  // what the node passed to ctx.record
  std::string error;                           // the node's own error message, if any
  // "hit": loaded from the stage cache instead of running; "miss": ran and was stored; "off": no
  // cache, or a node the cache never stands in for (its outputs have no binary form, or it
  // asks a live service).
  std::string cache = "off";
  // The node's stage-cache key (16 hex digits; empty without a cache): runs that share a key
  // share the result, so a benchmark can charge a loaded node the time it took when it ran.
  std::string cache_key;
};

struct RunResult {
  RunStatus status = RunStatus::Ok;
  std::optional<RunError> error;  // the first failure; set unless status is Ok
  std::vector<NodeRecord> nodes;  // in the graph's (topological) order
  std::string started_at;         // ISO 8601 UTC, "2026-11-22T07:30:00Z"
  double total_s = 0;
  int threads = 0;  // the thread count actually used
  uint64_t seed = 0;
  int64_t peak_rss_kb = 0;  // this process's own peak resident memory (VmHWM)
  // Every output produced, keyed "node.port", for tests and embedding callers.
  std::map<std::string, Value> values;

  bool ok() const { return status == RunStatus::Ok; }
  const NodeRecord* node(const std::string& id) const;
};

// Runs `graph` (validated: every type registered, inputs wired, topological order). Never throws
// for a node's failure: that is reported in the result. When options.out_dir is set, run.json is
// written there first with status "running" (atomically, replacing an earlier run's), then at
// the end, also after a failure, and the folders of cancelled nodes (stopped halfway) are
// removed.
RunResult execute(const Graph& graph, const Registry& registry, const RunOptions& options);

// The one-node/inline-graph test harness: loads `yaml` with load_graph_text (named "<inline>" in
// diagnostics) and executes it. A graph that fails validation throws std::invalid_argument with
// every diagnostic, one per line.
RunResult run_graph_text(const std::string& yaml, const Registry& registry,
                         const RunOptions& options = {}, const LoadOptions& load = {});

}  // namespace gslift
