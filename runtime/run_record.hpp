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
#include <string>
#include <utility>
#include <vector>

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

// `j` as indented JSON text, never throwing on bytes: every string and key that is not valid UTF-8
// (a Latin-1 folder name, a stray byte in a graph param or an error message) is written with
// its invalid bytes as "\xNN" (base/utf8.hpp), so run.json, batch markers and summaries survive
// and the real error is the one reported.
std::string json_text(const nlohmann::json& j);

// The headline metrics of a record: the evaluation nodes' (type eval.*) numeric records without
// per-class entries ("IoU/table") and counts ("queries", "views", "hits"), at most five, as
// ("<node>.<key>", value) in graph order. What `gslift sweep` and `gslift batch` print per run.
std::vector<std::pair<std::string, double>> headline_metrics(const nlohmann::json& record);

// Writes run_record_json with json_text and write_file_atomically.
void write_run_record(const std::filesystem::path& file, const Graph& graph,
                      const RunResult& result);

}  // namespace gslift
