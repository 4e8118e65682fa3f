#include "runtime/run_record.hpp"

#include "base/atomic_file.hpp"
#include "base/utf8.hpp"
#include "runtime/version.hpp"

namespace gslift {

using nlohmann::json;

json param_json(const ParamValue& v) {
  return std::visit([](const auto& x) { return json(x); }, v);
}

namespace {
json loc_json(const SourceLoc& loc) {
  return loc.file.empty() ? json() : json(loc.str());
}

json params_json(const std::map<std::string, ParamValue>& params) {
  json out = json::object();
  for (const auto& [name, value] : params) out[name] = param_json(value);
  return out;
}

json error_json(const RunError& e) {
  return {{"kind", to_string(e.kind)},
          {"node", e.node},
          {"type", e.type},
          {"loc", loc_json(e.loc)},
          {"message", e.message}};
}

json node_json(const NodeRecord& n) {
  json records = json::object();
  for (const auto& [key, value] : n.records)
    records[key] = std::visit([](const auto& x) { return json(x); }, value);
  json out = {{"id", n.id},
              {"type", n.type},
              {"status", to_string(n.status)},
              {"start_s", n.start_s},
              {"end_s", n.end_s},
              {"wall_s", n.end_s - n.start_s},
              {"peak_rss_mb", static_cast<double>(n.peak_rss_kb) / 1024.0},
              {"cache", n.cache},
              {"records", records}};
  if (!n.cache_key.empty()) out["cache_key"] = n.cache_key;
  if (n.status == NodeStatus::Failed) out["error"] = n.error;
  return out;
}
// A copy of `j` whose strings and keys are valid UTF-8 (escape_invalid_utf8), strings without
// terminal colour codes (a library's error message may carry them).
json with_valid_utf8(const json& j) {
  if (j.is_string())
    return escape_invalid_utf8(without_terminal_codes(j.get_ref<const std::string&>()));
  if (j.is_array()) {
    json out = json::array();
    for (const auto& e : j) out.push_back(with_valid_utf8(e));
    return out;
  }
  if (j.is_object()) {
    json out = json::object();
    for (const auto& [k, v] : j.items()) out[escape_invalid_utf8(k)] = with_valid_utf8(v);
    return out;
  }
  return j;
}
}  // namespace

std::string json_text(const json& j) {
  return with_valid_utf8(j).dump(2) + "\n";
}

json graph_json(const Graph& graph) {
  json nodes = json::array();
  for (const auto& n : graph.nodes) {
    json inputs = json::object();
    for (const auto& [port, ref] : n.inputs) inputs[port] = ref.str();
    nodes.push_back({{"id", n.id},
                     {"type", n.type},
                     {"loc", loc_json(n.loc)},
                     {"inputs", inputs},
                     {"params", params_json(n.params)}});
  }
  return {{"name", graph.name},
          {"files", graph.files},
          {"params", params_json(graph.params)},
          {"nodes", nodes}};
}

json run_record_json(const Graph& graph, const RunResult& result) {
  json nodes = json::array();
  for (const auto& n : result.nodes) nodes.push_back(node_json(n));
  return {{"gslift", {{"version", gslift_version()}, {"git", gslift_git_version()}}},
          {"graph", graph_json(graph)},
          {"run",
           {{"status", to_string(result.status)},
            {"error", result.error ? error_json(*result.error) : json()},
            {"seed", result.seed},
            {"threads", result.threads},
            {"started_at", result.started_at},
            {"total_s", result.total_s},
            {"peak_rss_mb", static_cast<double>(result.peak_rss_kb) / 1024.0}}},
          {"nodes", nodes}};
}

void write_run_record(const std::filesystem::path& file, const Graph& graph,
                      const RunResult& result) {
  write_file_atomically(file, json_text(run_record_json(graph, result)));
}

namespace {

// What the evaluation nodes count beside their metrics (queries asked, views scored, labels
// matched): sizes, not results, so no headline, table column or chart shows them as one.
bool is_count_record(const std::string& key) {
  for (const char* count : {"queries", "classes", "prompts", "target_views", "views", "gt_labels",
                            "pred_labels", "hits"})
    if (key == count) return true;
  return false;
}

}  // namespace

std::vector<std::pair<std::string, double>> headline_metrics(const nlohmann::json& record) {
  std::vector<std::pair<std::string, double>> out;
  if (!record.contains("nodes") || !record.at("nodes").is_array()) return out;
  for (const auto& n : record.at("nodes")) {
    if (n.value("type", std::string()).rfind("eval.", 0) != 0 || !n.contains("records")) continue;
    for (const auto& [key, value] : n.at("records").items())
      if (value.is_number() && key.find('/') == std::string::npos && !is_count_record(key) &&
          out.size() < 5)
        out.emplace_back(n.value("id", std::string()) + "." + key, value.get<double>());
  }
  return out;
}

}  // namespace gslift
