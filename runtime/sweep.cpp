#include "runtime/sweep.hpp"

#include <cmath>
#include <cstdio>
#include <set>
#include <stdexcept>

#include "base/csv_field.hpp"
#include "base/statistics.hpp"
#include "base/utf8.hpp"

namespace gslift {

using nlohmann::json;

GridAxis parse_grid(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw std::invalid_argument("--grid expects NODE.PARAM=V1,V2,..., got '" + printable(text) +
                                "'");
  GridAxis axis;
  axis.param = text.substr(0, eq);
  // Quotes and [] group only where they close: a quote or bracket that never does is a character
  // of its value, as in --set ("capture.path=a'b" was no value at all). Each scan that ends inside
  // a group marks the innermost opener as such a character and scans again ("[a,'b]" is one
  // value).
  std::set<size_t> literal;
  for (;;) {
    axis.values.clear();
    std::string value;
    std::vector<size_t> open;  // the positions of the open groups' openers, outermost first
    char quote = 0;
    for (size_t i = eq + 1; i <= text.size(); ++i) {
      const char c = i < text.size() ? text[i] : ',';
      if (literal.count(i) == 0) {
        if (quote) {
          if (c == quote) {
            quote = 0;
            open.pop_back();
          }
        } else if (c == '"' || c == '\'') {
          quote = c;
          open.push_back(i);
        } else if (c == '[') {
          open.push_back(i);
        } else if (c == ']' && !open.empty()) {
          open.pop_back();
        } else if (c == ',' && open.empty()) {
          if (value.empty())
            throw std::invalid_argument("--grid " + printable(text) +
                                        ": an empty value in the list");
          axis.values.push_back(value);
          value.clear();
          continue;
        }
      }
      value += c;
    }
    if (open.empty()) break;
    literal.insert(open.back());
  }
  std::set<std::string> seen;
  for (const auto& v : axis.values)
    if (!seen.insert(v).second)
      throw std::invalid_argument("--grid " + printable(text) + ": value '" + printable(v) +
                                  "' is listed twice");
  return axis;
}

namespace {
uint64_t parse_seed(const std::string& text, const std::string& whole) {
  size_t used = 0;
  unsigned long long v = 0;
  try {
    if (!text.empty() && text[0] != '-' && text[0] != '+') v = std::stoull(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size())
    throw std::invalid_argument("--seeds expects 0-4, 0,2,7 or 3, got '" + whole + "'");
  return v;
}
}  // namespace

std::vector<uint64_t> parse_seeds(const std::string& text) {
  std::vector<uint64_t> seeds;
  const auto dash = text.find('-');
  if (dash != std::string::npos && text.find(',') == std::string::npos) {
    const uint64_t first = parse_seed(text.substr(0, dash), text);
    const uint64_t last = parse_seed(text.substr(dash + 1), text);
    if (last < first || last - first >= 10000)
      throw std::invalid_argument("--seeds " + text +
                                  ": a range of 1 to 10000 seeds, first to last");
    for (uint64_t s = first; s <= last; ++s) seeds.push_back(s);
    return seeds;
  }
  size_t start = 0;
  while (start <= text.size()) {
    const size_t end = std::min(text.find(',', start), text.size());
    seeds.push_back(parse_seed(text.substr(start, end - start), text));
    start = end + 1;
  }
  return seeds;
}

std::vector<SweepPoint> sweep_points(const std::vector<GridAxis>& axes,
                                     const std::vector<uint64_t>& seeds,
                                     const std::vector<std::string>& inputs) {
  std::set<std::string> params;
  size_t runs = inputs.size() > 0 && seeds.size() > kMaxSweepRuns / inputs.size()
                    ? kMaxSweepRuns + 1
                    : seeds.size() * inputs.size();
  for (const auto& axis : axes) {
    if (!params.insert(axis.param).second)
      throw std::invalid_argument("--grid " + printable(axis.param) +
                                  " is given twice; list all its values in one --grid");
    const size_t n = axis.values.size();  // saturating: 10^6 values on 4 axes overflow
    runs = n > 0 && runs > kMaxSweepRuns / n ? kMaxSweepRuns + 1 : runs * n;
  }
  if (runs > kMaxSweepRuns)
    throw std::invalid_argument("the grid and seeds make more than " +
                                std::to_string(kMaxSweepRuns) +
                                " runs; a sweep is limited to that many (split it)");
  std::vector<std::map<std::string, std::string>> combos = {{}};
  for (const auto& axis : axes) {
    std::vector<std::map<std::string, std::string>> next;
    for (const auto& combo : combos)
      for (const auto& v : axis.values) {
        auto c = combo;
        c[axis.param] = v;
        next.push_back(std::move(c));
      }
    combos = std::move(next);
  }
  std::vector<SweepPoint> points;
  for (const auto& combo : combos)
    for (const auto& input : inputs)
      for (uint64_t seed : seeds) points.push_back({combo, seed, input});
  return points;
}

std::vector<std::string> sweep_point_sets(const SweepPoint& point) {
  const auto is_type = [](const std::string& param) {
    const std::string suffix = ".type";
    return param.size() > suffix.size() &&
           param.compare(param.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  std::vector<std::string> swaps, params;
  for (const auto& [param, value] : point.params)
    (is_type(param) ? swaps : params).push_back(param + "=" + value);
  swaps.insert(swaps.end(), params.begin(), params.end());
  return swaps;
}

SweepRun sweep_run_from_record(const json& run_json, SweepRun run) {
  const json& r = run_json.at("run");
  run.status = r.at("status").get<std::string>();
  run.total_s = r.at("total_s").get<double>();
  run.peak_rss_mb = r.at("peak_rss_mb").get<double>();
  if (r.contains("error") && r["error"].is_object())
    run.error = r["error"].value("node", std::string()).empty()
                    ? r["error"].value("message", std::string())
                    : "node '" + r["error"]["node"].get<std::string>() +
                          "' failed: " + r["error"].value("message", std::string());
  for (const auto& n : run_json.at("nodes")) {
    const std::string id = n.at("id").get<std::string>();
    if (n.value("status", std::string()) == "ok")
      run.node_wall_s[id] = n.at("wall_s").get<double>();
    for (const auto& [key, value] : n.at("records").items())
      if (value.is_number()) run.metrics[id + "." + key] = value.get<double>();
  }
  return run;
}

namespace {

json mean_std_json(const std::vector<double>& xs) {
  if (xs.empty()) return json();
  const auto [mean, sd] = mean_std(xs);
  return {{"mean", mean}, {"std", sd}};
}

std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", x);
  return buf;
}

}  // namespace

namespace {

// The first group's runs by (input, seed), and each metric's differences to them.
json paired_against(const std::vector<const SweepRun*>& base,
                    const std::vector<const SweepRun*>& members) {
  std::map<std::pair<std::string, uint64_t>, const SweepRun*> by_room;
  for (const SweepRun* r : base)
    if (r->status == "ok") by_room[{r->point.input, r->point.seed}] = r;
  std::map<std::string, std::vector<double>> diffs;
  for (const SweepRun* r : members) {
    if (r->status != "ok") continue;
    auto it = by_room.find({r->point.input, r->point.seed});
    if (it == by_room.end()) continue;
    for (const auto& [k, v] : r->metrics) {
      auto b = it->second->metrics.find(k);
      if (b != it->second->metrics.end()) diffs[k].push_back(v - b->second);
    }
  }
  json metrics = json::object();
  const auto finite_or_null = [](double x) { return std::isfinite(x) ? json(x) : json(); };
  for (const auto& [k, d] : diffs) {
    const MeanInterval m = mean_interval_95(d);
    metrics[k] = {{"n", m.n},
                  {"mean", m.mean},
                  {"low", finite_or_null(m.low)},
                  {"high", finite_or_null(m.high)}};
  }
  return metrics;
}

}  // namespace

json sweep_json(const std::string& graph, const std::vector<GridAxis>& axes,
                const std::vector<uint64_t>& seeds, const std::vector<SweepRun>& runs,
                const std::vector<std::string>& inputs) {
  json grid = json::object();
  for (const auto& a : axes) grid[a.param] = a.values;
  json rows = json::array();
  // Groups in first-seen order: the grid's own order.
  std::vector<std::map<std::string, std::string>> order;
  std::map<std::map<std::string, std::string>, std::vector<const SweepRun*>> groups;
  for (const auto& r : runs) {
    rows.push_back({{"dir", r.dir},
                    {"params", r.point.params},
                    {"seed", r.point.seed},
                    {"input", r.point.input.empty() ? json() : json(r.point.input)},
                    {"status", r.status},
                    {"error", r.error.empty() ? json() : json(r.error)},
                    {"total_s", r.total_s},
                    {"peak_rss_mb", r.peak_rss_mb},
                    {"metrics", r.metrics},
                    {"node_wall_s", r.node_wall_s}});
    if (!groups.count(r.point.params)) order.push_back(r.point.params);
    groups[r.point.params].push_back(&r);
  }
  json summary = json::array();
  for (const auto& params : order) {
    const auto& members = groups[params];
    std::map<std::string, std::vector<double>> values;
    std::vector<double> times, memory;
    int failed = 0;
    for (const SweepRun* r : members) {
      if (r->status != "ok") {
        ++failed;
        continue;
      }
      times.push_back(r->total_s);
      memory.push_back(r->peak_rss_mb);
      for (const auto& [k, v] : r->metrics) values[k].push_back(v);
    }
    json metrics = json::object();
    for (const auto& [k, v] : values) metrics[k] = mean_std_json(v);
    json group = {{"params", params},
                  {"n", members.size() - size_t(failed)},
                  {"failed", failed},
                  {"metrics", metrics},
                  {"total_s", mean_std_json(times)},
                  {"peak_rss_mb", mean_std_json(memory)}};
    if (params != order.front())
      group["paired"] = {{"against", order.front()},
                         {"metrics", paired_against(groups[order.front()], members)}};
    summary.push_back(std::move(group));
  }
  return {{"graph", graph},   {"grid", grid}, {"seeds", seeds},
          {"inputs", inputs}, {"runs", rows}, {"summary", summary}};
}

std::string sweep_runs_csv(const std::vector<GridAxis>& axes, const std::vector<SweepRun>& runs) {
  std::set<std::string> metric_keys, nodes;
  for (const auto& r : runs) {
    for (const auto& [k, v] : r.metrics) metric_keys.insert(k);
    for (const auto& [k, v] : r.node_wall_s) nodes.insert(k);
  }
  bool with_input = false;
  for (const auto& r : runs) with_input = with_input || !r.point.input.empty();
  std::string out = with_input ? "run,seed,input,status,error" : "run,seed,status,error";
  for (const auto& a : axes) out += "," + csv_field(a.param);
  out += ",total_s,peak_rss_mb";
  for (const auto& k : metric_keys) out += "," + csv_field(k);
  for (const auto& n : nodes) out += "," + csv_field("wall_s." + n);
  out += "\n";
  for (const auto& r : runs) {
    out += r.dir + "," + std::to_string(r.point.seed) + ",";
    if (with_input) out += csv_field(r.point.input) + ",";
    out += r.status + "," + csv_field(r.error);
    for (const auto& a : axes) out += "," + csv_field(r.point.params.at(a.param));
    out += "," + number(r.total_s) + "," + number(r.peak_rss_mb);
    for (const auto& k : metric_keys) {
      auto it = r.metrics.find(k);
      out += "," + (it == r.metrics.end() ? std::string() : number(it->second));
    }
    for (const auto& n : nodes) {
      auto it = r.node_wall_s.find(n);
      out += "," + (it == r.node_wall_s.end() ? std::string() : number(it->second));
    }
    out += "\n";
  }
  return out;
}

std::string sweep_summary_csv(const std::vector<GridAxis>& axes, const json& sweep) {
  std::set<std::string> keys;
  for (const auto& s : sweep.at("summary"))
    for (const auto& [k, v] : s.at("metrics").items()) keys.insert(k);
  std::string out;
  for (const auto& a : axes) out += csv_field(a.param) + ",";
  out += "n,failed,total_s_mean,total_s_std,peak_rss_mb_mean,peak_rss_mb_std";
  for (const auto& k : keys) out += "," + csv_field(k + "_mean") + "," + csv_field(k + "_std");
  out += "\n";
  const auto pair = [](const json& ms) {
    return ms.is_null() ? std::string(",")
                        : number(ms["mean"].get<double>()) + "," + number(ms["std"].get<double>());
  };
  for (const auto& s : sweep.at("summary")) {
    for (const auto& a : axes) out += csv_field(s["params"][a.param].get<std::string>()) + ",";
    out += std::to_string(s["n"].get<int>()) + "," + std::to_string(s["failed"].get<int>()) + ",";
    out += pair(s["total_s"]) + "," + pair(s["peak_rss_mb"]);
    for (const auto& k : keys)
      out += "," + (s["metrics"].contains(k) ? pair(s["metrics"][k]) : std::string(","));
    out += "\n";
  }
  return out;
}

std::string sweep_table(const std::vector<GridAxis>& axes, const json& sweep,
                        const std::vector<std::string>& headline) {
  std::string out;
  const auto line = [&](const std::vector<std::string>& cells) {
    for (size_t i = 0; i < cells.size(); ++i) out += (i ? " | " : "| ") + cells[i];
    out += " |\n";
  };
  std::vector<std::string> head;
  for (const auto& a : axes) head.push_back(a.param);
  head.insert(head.end(), {"ok", "failed", "time s"});
  head.insert(head.end(), headline.begin(), headline.end());
  line(head);
  const auto cell = [](const json& ms) {
    if (ms.is_null()) return std::string("-");
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.3g +- %.2g", ms["mean"].get<double>(),
                  ms["std"].get<double>());
    return std::string(buf);
  };
  for (const auto& s : sweep.at("summary")) {
    std::vector<std::string> cells;
    for (const auto& a : axes) cells.push_back(s["params"][a.param].get<std::string>());
    cells.push_back(std::to_string(s["n"].get<int>()));
    cells.push_back(std::to_string(s["failed"].get<int>()));
    cells.push_back(cell(s["total_s"]));
    for (const auto& k : headline)
      cells.push_back(s["metrics"].contains(k) ? cell(s["metrics"][k]) : std::string("-"));
    line(cells);
  }
  for (const auto& s : sweep.at("summary")) {
    if (!s.contains("paired")) continue;
    std::string label, against;
    for (const auto& a : axes) {
      label += (label.empty() ? "" : " ") + a.param + "=" + s["params"][a.param].get<std::string>();
      against += (against.empty() ? "" : " ") + s["paired"]["against"][a.param].get<std::string>();
    }
    out += "paired, " + label + " minus " + against + ":";
    for (const auto& k : headline) {
      const json& m = s["paired"]["metrics"].value(k, json());
      if (m.is_null()) continue;
      char buf[128];
      if (m["low"].is_null())
        std::snprintf(buf, sizeof buf, " %s %+.3g (n %d)", k.c_str(), m["mean"].get<double>(),
                      m["n"].get<int>());
      else
        std::snprintf(buf, sizeof buf, " %s %+.3g [%+.3g, %+.3g] (n %d)", k.c_str(),
                      m["mean"].get<double>(), m["low"].get<double>(), m["high"].get<double>(),
                      m["n"].get<int>());
      out += buf;
    }
    out += "\n";
  }
  return out;
}

}  // namespace gslift
