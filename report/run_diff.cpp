#include "report/run_diff.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "base/utf8.hpp"

namespace gslift::report {

namespace {

using nlohmann::json;

constexpr const char* kAbsent = "(absent)";

Change change(const std::string& what, const json* a, const json* b) {
  Change c{what, a ? value_text(*a) : kAbsent, b ? value_text(*b) : kAbsent};
  if (a && b && a->is_number() && b->is_number()) {
    c.numeric = true;
    c.delta = b->get<double>() - a->get<double>();
  }
  return c;
}

Change number_change(const std::string& what, double a, double b) {
  return {what, number_text(a), number_text(b), true, b - a};
}

// Values of two maps that are not equal (a key in one only counts as a change).
void compare_maps(const std::string& prefix, const std::map<std::string, json>& a,
                  const std::map<std::string, json>& b, std::vector<Change>& out, size_t& same) {
  std::set<std::string> keys;
  for (const auto& [k, v] : a) keys.insert(k);
  for (const auto& [k, v] : b) keys.insert(k);
  for (const auto& k : keys) {
    auto ia = a.find(k), ib = b.find(k);
    const json* va = ia == a.end() ? nullptr : &ia->second;
    const json* vb = ib == b.end() ? nullptr : &ib->second;
    if (va && vb && *va == *vb) {
      ++same;
      continue;
    }
    out.push_back(change(prefix + k, va, vb));
  }
}

std::string line(const Change& c) {
  // Values and names come from the runs' files: capped and with control characters escaped.
  std::string s = "  " + printable(c.what) + ": " + printable(c.a) + " -> " + printable(c.b);
  if (c.numeric) {
    char buf[64];
    std::snprintf(buf, sizeof buf, " (%+.6g", c.delta);
    s += buf;
    const double a = std::strtod(c.a.c_str(), nullptr);
    if (a != 0 && std::isfinite(a)) {
      std::snprintf(buf, sizeof buf, ", %+.2f%%", 100 * c.delta / std::fabs(a));
      s += buf;
    }
    s += ")";
  }
  return s + "\n";
}

std::string section(const char* title, const std::vector<Change>& changes) {
  if (changes.empty()) return {};
  std::string s = std::string(title) + ":\n";
  for (const auto& c : changes) s += line(c);
  return s;
}

}  // namespace

bool is_time_record(const std::string& key) {
  // A word of the name (split at '_', '.', '/') that is a unit of time, wherever it sits:
  // "seconds", "wall_s", "ms_per_view", "select_ms_median".
  static const std::set<std::string> units = {"s", "ms", "us", "ns", "sec", "secs", "seconds"};
  size_t start = 0;
  while (start <= key.size()) {
    const size_t end = std::min(key.find_first_of("_./", start), key.size());
    if (units.count(key.substr(start, end - start))) return true;
    start = end + 1;
  }
  return false;
}

RunDiff diff_runs(const RunRecord& a, const RunRecord& b) {
  RunDiff d;
  if (a.status != b.status) d.status.push_back({"run status", a.status, b.status});
  if (a.error != b.error)
    d.status.push_back(
        {"run error", a.error.empty() ? "none" : a.error, b.error.empty() ? "none" : b.error});
  if (a.graph_name != b.graph_name) d.graph.push_back({"graph name", a.graph_name, b.graph_name});
  size_t same_graph_params = 0;
  compare_maps("graph param ", a.graph_params, b.graph_params, d.graph, same_graph_params);

  // Nodes in A's order, then those only in B.
  for (const auto& ga : a.graph) {
    const GraphNode* gb = b.graph_node(ga.id);
    if (!gb) {
      d.graph.push_back({"node " + ga.id, ga.type, kAbsent});
      continue;
    }
    if (ga.type != gb->type) d.graph.push_back({ga.id + " type", ga.type, gb->type});
    std::set<std::string> ports;
    for (const auto& [p, ref] : ga.inputs) ports.insert(p);
    for (const auto& [p, ref] : gb->inputs) ports.insert(p);
    for (const auto& p : ports) {
      auto ia = ga.inputs.find(p), ib = gb->inputs.find(p);
      const std::string ra = ia == ga.inputs.end() ? kAbsent : ia->second;
      const std::string rb = ib == gb->inputs.end() ? kAbsent : ib->second;
      if (ra != rb) d.graph.push_back({ga.id + " input " + p, ra, rb});
    }
    compare_maps(ga.id + ".", ga.params, gb->params, d.params, d.same_params);
  }
  for (const auto& gb : b.graph)
    if (!a.graph_node(gb.id)) d.graph.push_back({"node " + gb.id, kAbsent, gb.type});

  for (const auto& na : a.nodes) {
    const NodeRun* nb = b.node(na.id);
    if (!nb) continue;
    if (na.status != nb->status) d.status.push_back({na.id + " status", na.status, nb->status});
    // Records that measure time go with the wall times.
    std::map<std::string, json> ra, rb, ta, tb;
    for (const auto& [k, v] : na.records) (is_time_record(k) ? ta : ra)[k] = v;
    for (const auto& [k, v] : nb->records) (is_time_record(k) ? tb : rb)[k] = v;
    compare_maps(na.id + ".", ra, rb, d.records, d.same_records);
    size_t same_time = 0;
    compare_maps(na.id + ".", ta, tb, d.timing, same_time);
    d.timing.push_back(number_change(na.id + " wall_s", na.wall_s, nb->wall_s));
    if (na.cache != nb->cache)
      d.timing.push_back({na.id + " cache", na.cache.empty() ? kAbsent : na.cache,
                          nb->cache.empty() ? kAbsent : nb->cache});
  }
  d.timing.insert(d.timing.begin(), {number_change("total_s", a.total_s, b.total_s),
                                     number_change("peak_rss_mb", a.peak_rss_mb, b.peak_rss_mb)});
  return d;
}

std::string diff_text(const RunDiff& d, const RunRecord& a, const RunRecord& b) {
  const auto head = [](const char* mark, const RunRecord& r) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.2f s", r.total_s);
    return std::string(mark) + " " + printable(r.dir.string()) + " (" + printable(r.graph_name) +
           ", " + printable(r.status) + ", " + buf + ", seed " + std::to_string(r.seed) + ")\n";
  };
  std::string s = head("---", a) + head("+++", b);
  s += section("status", d.status);
  s += section("graph", d.graph);
  s += section("params", d.params);
  s += section("records", d.records);
  s += section("time and memory (not counted as differences)", d.timing);
  s += std::to_string(d.same_params) + " params and " + std::to_string(d.same_records) +
       " records are the same; " +
       (d.differs() ? "the runs differ" : "no differences beyond time and memory") + "\n";
  return s;
}

}  // namespace gslift::report
