// run.json: everything needed to trust and reproduce a result, written beside it (also when the
// run failed). Fields (docs/cli.md "run.json"):
//   gslift   {version, git}
//   graph    {name, files, params {name: value}, nodes [{id, type, loc, inputs {port: "node.port"},
//             params {name: value}}]}  -- the resolved graph, every param with its value
//   run      {status, error {kind, node, type, loc, message} | null, seed, threads, started_at,
//             total_s, peak_rss_mb}
//   nodes    [{id, type, status, start_s, end_s, wall_s, peak_rss_mb (process peak at the node's
//             end), records {key: number|string},
//             error (only when the node failed)}]
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

#include "graph/graph.hpp"
#include "runtime/executor.hpp"

namespace gslift {

// A param value as JSON: numbers, booleans, strings and arrays of them.
nlohmann::json param_json(const ParamValue& v);

// The resolved graph (the "graph" object above).
nlohmann::json graph_json(const Graph& graph);

// The whole record.
nlohmann::json run_record_json(const Graph& graph, const RunResult& result);

// Writes run_record_json, indented, with write_file_atomically.
void write_run_record(const std::filesystem::path& file, const Graph& graph,
                      const RunResult& result);

}  // namespace gslift
