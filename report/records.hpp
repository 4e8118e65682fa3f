// What `gslift report` and `gslift diff` read: a run folder's run.json (runtime/run_record.hpp,
// docs/cli.md "run.json") and a sweep folder's sweep.json (docs/cli.md "gslift sweep"), as plain
// data. Reading only: the formats are written by the runtime. Params and records keep their JSON
// values (numbers, strings, booleans, arrays), because a report prints them as they were written.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace gslift::report {

// One node of the resolved graph (run.json "graph.nodes[]").
struct GraphNode {
  std::string id;
  std::string type;
  std::string loc;                            // file:line:col, empty when unknown
  std::map<std::string, std::string> inputs;  // port -> "node.port"
  std::map<std::string, nlohmann::json> params;
};

// How one node ran (run.json "nodes[]").
struct NodeRun {
  std::string id;
  std::string type;
  std::string status;  // ok, failed, cancelled, pending
  double start_s = 0, end_s = 0, wall_s = 0, peak_rss_mb = 0;
  std::map<std::string, nlohmann::json> records;  // number or string
  std::string error;                              // failed nodes only
  std::string cache;                              // hit, miss, off; empty when not recorded
};

struct RunRecord {
  std::filesystem::path dir;
  std::string version, git;
  std::string graph_name;
  std::vector<std::string> graph_files;
  std::map<std::string, nlohmann::json> graph_params;
  std::vector<GraphNode> graph;  // topological order, as written
  std::vector<NodeRun> nodes;
  std::string status;  // ok, failed, interrupted
  std::string error;   // the run's error as one line, empty when none
  uint64_t seed = 0;
  int threads = 0;
  std::string started_at;
  double total_s = 0, peak_rss_mb = 0;
  // The evaluation nodes' summary metrics, ("<node>.<key>", value) in graph order
  // (runtime/run_record.hpp headline_metrics: what sweeps and batches print too).
  std::vector<std::pair<std::string, double>> headline;

  const NodeRun* node(const std::string& id) const;
  const GraphNode* graph_node(const std::string& id) const;
  // Whether any node says whether it came from the stage cache.
  bool has_cache_column() const;
  // How many nodes were loaded from the stage cache instead of run.
  size_t cache_hits() const;
};

// Reads DIR/run.json. Throws InputError naming the path when DIR or run.json is missing, or
// run.json is not JSON or lacks the fields above.
RunRecord read_run_record(const std::filesystem::path& dir);

struct MeanStd {
  double mean = 0, std = 0;
};

// One run of a sweep (sweep.json "runs[]"); numbers a failed run lacks are NaN.
struct SweepRun {
  std::string dir;                            // relative to the sweep folder
  std::map<std::string, std::string> params;  // NODE.PARAM -> value as given on the grid
  uint64_t seed = 0;
  std::string status;  // ok, failed
  std::string error;
  double total_s = 0, peak_rss_mb = 0;
  std::map<std::string, double> metrics;  // NODE.KEY -> value (numeric records only)
};

// The runs of one grid point, over seeds (sweep.json "summary[]").
struct SweepGroup {
  std::map<std::string, std::string> params;
  int n = 0, failed = 0;
  std::map<std::string, MeanStd> metrics;
  MeanStd total_s, peak_rss_mb;
};

struct SweepRecord {
  std::filesystem::path dir;
  std::string graph;
  std::map<std::string, std::vector<std::string>> grid;  // the varied params and their values
  std::vector<uint64_t> seeds;
  // The metrics a person compares first (the evaluation nodes' summary metrics); empty when the
  // sweep names none.
  std::vector<std::string> headline;
  std::vector<SweepRun> runs;
  std::vector<SweepGroup> summary;
};

// Whether DIR holds a sweep.json (else it is taken as a run folder).
bool is_sweep_dir(const std::filesystem::path& dir);

// Reads DIR/sweep.json; throws InputError naming the path, as read_run_record.
SweepRecord read_sweep_record(const std::filesystem::path& dir);

// A number as a person reads it: whole numbers in full (57616, 142140952), others with 6
// significant digits (56.4995).
std::string number_text(double value);

// A JSON value as a person reads it: strings without quotes, numbers as number_text.
std::string value_text(const nlohmann::json& value);

}  // namespace gslift::report
