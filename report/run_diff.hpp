// `gslift diff RUN_A RUN_B`: what changed between two runs, read from their run.json files. Params,
// records, the graph's structure and the status are differences; time (the run's, each node's and
// records that measure time, e.g. recon.seconds), memory and cache state always differ a little
// between reruns and are shown apart, never counted (docs/cli.md "gslift diff").
#pragma once

#include <string>
#include <vector>

#include "report/records.hpp"

namespace gslift::report {

// One thing that is not the same: `what` names it ("lift.sigma", "node 'x' added"), `a` and `b`
// are the two values as text ("(absent)" where a run lacks it); numbers carry their delta b - a.
struct Change {
  std::string what;
  std::string a, b;
  bool numeric = false;
  double delta = 0;
};

struct RunDiff {
  std::vector<Change> status;   // the run's status and error, nodes' status
  std::vector<Change> graph;    // graph name and params, nodes added, removed, retyped, rewired
  std::vector<Change> params;   // NODE.PARAM, nodes in both runs
  std::vector<Change> records;  // NODE.KEY, nodes in both runs
  std::vector<Change> timing;   // total_s, peak_rss_mb, wall_s, cache, time records (not counted)
  size_t same_params = 0, same_records = 0;

  // Whether anything but time, memory and cache state differs.
  bool differs() const {
    return !status.empty() || !graph.empty() || !params.empty() || !records.empty();
  }
};

RunDiff diff_runs(const RunRecord& a, const RunRecord& b);

// Whether a record measures time, by its name: one of its words (split at _ . /) is a unit of
// time (s, ms, us, ns, sec, secs, seconds), wherever it sits: "wall_s", "select_ms_median".
bool is_time_record(const std::string& key);

// The diff as the command prints it: a header naming both runs, then one section per kind of
// change, "what: a -> b (delta, relative)" a line.
std::string diff_text(const RunDiff& diff, const RunRecord& a, const RunRecord& b);

}  // namespace gslift::report
