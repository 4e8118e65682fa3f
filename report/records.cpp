#include "report/records.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

#include "base/errors.hpp"
#include "base/json_read.hpp"
#include "runtime/run_record.hpp"

namespace gslift::report {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json read_json(const fs::path& dir, const char* name) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError(dir.string() + " is not a folder");
  const fs::path file = dir / name;
  if (!fs::is_regular_file(file, ec))
    throw InputError(dir.string() + " holds no " + name + " (" + file.string() + " is missing)");
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  if (!in && !in.eof()) throw InputError("cannot read " + file.string());
  try {
    return parse_json(text.str());
  } catch (const json::parse_error& e) {
    throw InputError(file.string() + " is not valid JSON: " + e.what());
  }
}

// The JSON library's type errors ("type must be number, but is string") do not say where; the
// readers below catch them and name the file.
const json& member(const json& object, const char* key) {
  if (!object.is_object() || !object.contains(key))
    throw json::other_error::create(0, std::string("missing field '") + key + "'", &object);
  return object.at(key);
}

std::string optional_string(const json& object, const char* key) {
  if (!object.contains(key) || object.at(key).is_null()) return {};
  return object.at(key).get<std::string>();
}

double number_or_nan(const json& object, const char* key) {
  if (!object.contains(key) || !object.at(key).is_number())
    return std::numeric_limits<double>::quiet_NaN();
  return object.at(key).get<double>();
}

std::map<std::string, json> json_map(const json& object) {
  std::map<std::string, json> out;
  if (object.is_null()) return out;
  if (!object.is_object()) throw json::other_error::create(0, "expected an object", &object);
  for (const auto& [k, v] : object.items()) out[k] = v;
  return out;
}

// run.json "run.error": {kind, node, type, loc, message} as one line.
std::string error_line(const json& e) {
  if (e.is_null()) return {};
  if (e.is_string()) return e.get<std::string>();
  std::string line;
  const std::string loc = optional_string(e, "loc"), node = optional_string(e, "node");
  if (!loc.empty()) line += loc + ": ";
  if (!node.empty()) line += "node '" + node + "' (" + optional_string(e, "type") + "): ";
  line += optional_string(e, "message");
  const std::string kind = optional_string(e, "kind");
  return kind.empty() ? line : line + " [" + kind + "]";
}

MeanStd mean_std(const json& object, const char* key) {
  if (!object.contains(key) || !object.at(key).is_object())
    return {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  return {number_or_nan(object.at(key), "mean"), number_or_nan(object.at(key), "std")};
}

std::map<std::string, std::string> string_map(const json& object) {
  std::map<std::string, std::string> out;
  for (const auto& [k, v] : json_map(object)) out[k] = value_text(v);
  return out;
}

}  // namespace

std::string number_text(double value) {
  char buf[64];
  if (std::isfinite(value) && value == std::floor(value) && std::fabs(value) < 1e15)
    std::snprintf(buf, sizeof buf, "%.0f", value);
  else
    std::snprintf(buf, sizeof buf, "%.6g", value);
  return buf;
}

std::string value_text(const json& value) {
  if (value.is_string()) return value.get<std::string>();
  if (value.is_number()) return number_text(value.get<double>());
  return value.dump();
}

const NodeRun* RunRecord::node(const std::string& id) const {
  for (const auto& n : nodes)
    if (n.id == id) return &n;
  return nullptr;
}

const GraphNode* RunRecord::graph_node(const std::string& id) const {
  for (const auto& n : graph)
    if (n.id == id) return &n;
  return nullptr;
}

size_t RunRecord::cache_hits() const {
  size_t n = 0;
  for (const auto& node : nodes) n += node.cache == "hit";
  return n;
}

bool RunRecord::has_cache_column() const {
  for (const auto& n : nodes)
    if (!n.cache.empty()) return true;
  return false;
}

RunRecord read_run_record(const fs::path& dir) {
  const json j = read_json(dir, "run.json");
  RunRecord r;
  r.dir = dir;
  try {
    const json& gs = member(j, "gslift");
    r.version = optional_string(gs, "version");
    r.git = optional_string(gs, "git");
    const json& graph = member(j, "graph");
    r.graph_name = optional_string(graph, "name");
    if (graph.contains("files")) r.graph_files = graph.at("files").get<std::vector<std::string>>();
    if (graph.contains("params")) r.graph_params = json_map(graph.at("params"));
    for (const json& n : member(graph, "nodes")) {
      GraphNode g;
      g.id = member(n, "id").get<std::string>();
      g.type = member(n, "type").get<std::string>();
      g.loc = optional_string(n, "loc");
      if (n.contains("inputs")) g.inputs = n.at("inputs").get<std::map<std::string, std::string>>();
      if (n.contains("params")) g.params = json_map(n.at("params"));
      r.graph.push_back(std::move(g));
    }
    for (const json& n : member(j, "nodes")) {
      NodeRun run;
      run.id = member(n, "id").get<std::string>();
      run.type = optional_string(n, "type");
      run.status = member(n, "status").get<std::string>();
      run.start_s = member(n, "start_s").get<double>();
      run.end_s = member(n, "end_s").get<double>();
      run.wall_s = n.contains("wall_s") ? n.at("wall_s").get<double>() : run.end_s - run.start_s;
      run.peak_rss_mb = n.value("peak_rss_mb", 0.0);
      if (n.contains("records")) run.records = json_map(n.at("records"));
      run.error = optional_string(n, "error");
      run.cache = optional_string(n, "cache");
      r.nodes.push_back(std::move(run));
    }
    const json& run = member(j, "run");
    r.status = member(run, "status").get<std::string>();
    r.error = run.contains("error") ? error_line(run.at("error")) : std::string();
    r.seed = run.value("seed", uint64_t{0});
    r.threads = run.value("threads", 0);
    r.started_at = optional_string(run, "started_at");
    r.total_s = run.value("total_s", 0.0);
    r.peak_rss_mb = run.value("peak_rss_mb", 0.0);
    r.headline = headline_metrics(j);
  } catch (const json::exception& e) {
    throw InputError((dir / "run.json").string() + " is not a gslift run record: " + e.what());
  }
  return r;
}

namespace {

// gslift report writes each run's report.html into its folder: a sweep.json (from anywhere)
// whose runs[].dir is absolute, climbs out with "..", or is a symlink out must not make it write
// elsewhere.
void check_inside_sweep(const fs::path& sweep_dir, const std::string& run_dir) {
  const fs::path rel(run_dir);
  bool inside = !run_dir.empty() && rel.is_relative() && !rel.has_root_name();
  for (const auto& part : rel.lexically_normal()) inside = inside && part != "..";
  std::error_code ec, ec2;
  const fs::path root = fs::weakly_canonical(sweep_dir, ec);
  const fs::path target = fs::weakly_canonical(sweep_dir / rel, ec2);
  if (inside && !ec && !ec2) {
    const fs::path up = target.lexically_relative(root);
    inside = !up.empty() && *up.begin() != "..";
  }
  if (!inside)
    throw InputError((sweep_dir / "sweep.json").string() + ": run folder '" + run_dir +
                     "' is not inside the sweep folder");
}

}  // namespace

bool is_sweep_dir(const fs::path& dir) {
  std::error_code ec;
  return fs::is_regular_file(dir / "sweep.json", ec);
}

SweepRecord read_sweep_record(const fs::path& dir) {
  const json j = read_json(dir, "sweep.json");
  SweepRecord s;
  s.dir = dir;
  try {
    s.graph = optional_string(j, "graph");
    if (j.contains("grid"))
      for (const auto& [name, values] : j.at("grid").items())
        for (const json& v : values) s.grid[name].push_back(value_text(v));
    if (j.contains("seeds")) s.seeds = j.at("seeds").get<std::vector<uint64_t>>();
    if (j.contains("headline")) s.headline = j.at("headline").get<std::vector<std::string>>();
    for (const json& r : member(j, "runs")) {
      SweepRun run;
      run.dir = member(r, "dir").get<std::string>();
      check_inside_sweep(dir, run.dir);
      if (r.contains("params")) run.params = string_map(r.at("params"));
      run.seed = r.value("seed", uint64_t{0});
      run.status = member(r, "status").get<std::string>();
      run.error = optional_string(r, "error");
      run.total_s = number_or_nan(r, "total_s");
      run.peak_rss_mb = number_or_nan(r, "peak_rss_mb");
      if (r.contains("metrics") && r.at("metrics").is_object())
        for (const auto& [k, v] : r.at("metrics").items())
          if (v.is_number()) run.metrics[k] = v.get<double>();
      s.runs.push_back(std::move(run));
    }
    if (j.contains("summary"))
      for (const json& g : j.at("summary")) {
        SweepGroup group;
        if (g.contains("params")) group.params = string_map(g.at("params"));
        group.n = g.value("n", 0);
        group.failed = g.value("failed", 0);
        if (g.contains("metrics") && g.at("metrics").is_object())
          for (const auto& [k, v] : g.at("metrics").items())
            if (v.is_object()) group.metrics[k] = mean_std(g.at("metrics"), k.c_str());
        group.total_s = mean_std(g, "total_s");
        group.peak_rss_mb = mean_std(g, "peak_rss_mb");
        s.summary.push_back(std::move(group));
      }
  } catch (const json::exception& e) {
    throw InputError((dir / "sweep.json").string() + " is not a gslift sweep record: " + e.what());
  }
  return s;
}

}  // namespace gslift::report
