// The experiment layer's charts (issue 15) from the sweeps of bench/experiments/run.sh:
//  - speed_accuracy.svg: x = wall time of the whole graph (a cold run: a node loaded from the stage
//    cache is charged the wall time it took in the run that computed it, found by its cache key),
//    y = the method's headline metric (methods.tsv), a point per method, variant and budget with
//    error bars over seeds, series per method, the Pareto front drawn;
//  - memory_accuracy.svg: the same against peak memory (a loaded node charged its computing run's
//    peak);
//  - budget_<method>_<param>.svg: the headline against each budget axis (budgets.tsv), with the
//    knee: the smallest budget whose mean is within one standard deviation of the best mean;
//  - experiments.json: every point, the fronts per method and the knees.
//   experiments_chart EXPERIMENTS_DIR TSV_DIR RESULTS_DIR
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/atomic_file.hpp"
#include "base/statistics.hpp"
#include "bench/common/json_file.hpp"
#include "bench/common/tsv.hpp"
#include "report/charts.hpp"
#include "report/pareto.hpp"

using namespace gslift;
using bench::read_json_or_discarded;
using bench::read_tsv;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// What a node cost where it ran (its cache key's miss).
struct Cost {
  double wall_s = 0, peak_mb = 0;
};

struct Point {
  std::string method, kind, name;  // kind: default, variant, budget
  std::string param, value;        // budget axis and value
  std::vector<double> metric, time_s, peak_mb, gaussians;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: experiments_chart EXPERIMENTS_DIR TSV_DIR RESULTS_DIR\n";
    return 2;
  }
  const fs::path dir = argv[1], tsv = argv[2], results = argv[3];
  std::map<std::string, std::string> headline;  // method -> node.record
  std::vector<std::string> methods;
  for (const auto& m : read_tsv(tsv / "methods.tsv"))
    if (m.size() >= 3) {
      methods.push_back(m[0]);
      headline[m[0]] = m[2];
    }

  // Every run of every sweep, with its run.json; then the cost of each cache key where it missed.
  struct Run {
    std::string sweep;
    json row, record;
  };
  std::vector<Run> runs;
  std::map<std::string, Cost> costs;
  for (const auto& e : fs::directory_iterator(dir)) {
    const json sweep = read_json_or_discarded(e.path() / "sweep.json");
    if (!sweep.is_object()) continue;
    for (const auto& row : sweep["runs"]) {
      Run r{e.path().filename().string(), row,
            read_json_or_discarded(e.path() / row["dir"].get<std::string>() / "run.json")};
      if (!r.record.is_object()) continue;
      for (const auto& n : r.record["nodes"])
        if (n.value("cache", "") == "miss" && n.contains("cache_key"))
          costs[n["cache_key"]] = {n["wall_s"].get<double>(), n["peak_rss_mb"].get<double>()};
      runs.push_back(std::move(r));
    }
  }

  // Points: sweep x params, over seeds (the seed is in the input spec, "{seed}").
  std::map<std::string, Point> points;
  std::vector<std::string> order;
  int uncharged = 0;
  for (const auto& r : runs) {
    if (r.row["status"] != "ok") continue;
    std::string method, kind = "default", name;
    const std::string& s = r.sweep;
    for (const auto& m : methods) {
      if (s == "method_" + m) method = m, name = m;
      if (s.rfind("budget_" + m + "_", 0) == 0) method = m, kind = "budget";
      if (s.rfind("variant_" + m + "_", 0) == 0)
        method = m, kind = "variant", name = m + " " + s.substr(9 + m.size());
    }
    if (method.empty()) continue;
    std::string param, value;
    for (const auto& [p, v] : r.row["params"].items()) param = p, value = v.get<std::string>();
    if (kind == "budget") {
      // The capture seed is not part of the budget: "embedded:or?seed=2&width=320" -> "320".
      if (param == "input") {
        const auto w = value.find("width=");
        value = w == std::string::npos ? "640" : value.substr(w + 6, value.find('&', w) - w - 6);
        param = "width";
      }
      name = method + " " + param + "=" + value;
    }
    const std::string key = kind + "|" + name;
    if (!points.count(key)) order.push_back(key);
    Point& p = points[key];
    p.method = method, p.kind = kind, p.name = name, p.param = param, p.value = value;
    const auto& metrics = r.row["metrics"];
    if (!metrics.contains(headline[method])) continue;
    double time = r.record["run"]["total_s"].get<double>();
    double peak = r.record["run"]["peak_rss_mb"].get<double>();
    for (const auto& n : r.record["nodes"]) {
      if (n.value("cache", "") != "hit") continue;
      auto c = costs.find(n.value("cache_key", ""));
      if (c == costs.end()) {
        ++uncharged;
        continue;
      }
      time += std::max(0.0, c->second.wall_s - n["wall_s"].get<double>());
      peak = std::max(peak, c->second.peak_mb);
    }
    p.metric.push_back(metrics[headline[method]].get<double>());
    p.time_s.push_back(time);
    p.peak_mb.push_back(peak);
    if (metrics.contains("recon.gaussians")) p.gaussians.push_back(metrics["recon.gaussians"]);
  }

  json doc = {{"benchmark", "experiments"},
              {"time",
               "wall time of the whole graph as a cold run (cache hits charged their "
               "computing run's time), 2 threads"},
              {"nodes_without_cost", uncharged},
              {"points", json::array()},
              {"pareto", json::object()},
              {"knees", json::array()}};
  report::ScatterChart speed, memory;
  speed.x_label = "wall time of the whole graph (s)";
  memory.x_label = "peak memory (MB)";
  speed.y_label = memory.y_label = "headline metric (%): mIoU, SAGA mIoU, detector fusion CA";
  speed.series_names = memory.series_names = methods;
  speed.pareto = memory.pareto = true;
  std::map<std::string, std::vector<std::pair<size_t, report::ChartPoint>>> per_method;
  for (const auto& key : order) {
    const Point& p = points[key];
    if (p.metric.empty()) continue;
    const auto [m, ms] = mean_std(p.metric);
    const auto [t, ts] = mean_std(p.time_s);
    const auto [mb, mbs] = mean_std(p.peak_mb);
    const int series = int(std::find(methods.begin(), methods.end(), p.method) - methods.begin());
    const std::string tag = p.kind == "default" ? p.method : "";
    speed.points.push_back({t, ts, m, ms, p.name, tag, series});
    memory.points.push_back({mb, mbs, m, ms, p.name, tag, series});
    json pj = {{"method", p.method},       {"kind", p.kind},    {"name", p.name},
               {"seeds", p.metric.size()}, {"metric", {m, ms}}, {"time_s", {t, ts}},
               {"peak_mb", {mb, mbs}}};
    if (!p.gaussians.empty()) pj["gaussians"] = mean_std(p.gaussians).first;
    if (p.kind == "budget") pj["budget"] = {p.param, p.value};
    per_method[p.method].push_back({doc["points"].size(), {t, m}});
    doc["points"].push_back(pj);
  }
  for (const auto& [method, pts] : per_method) {
    std::vector<report::ChartPoint> xy;
    for (const auto& [i, c] : pts) xy.push_back(c);
    json front = json::array();
    for (size_t i : report::pareto_front(xy, false))
      front.push_back(doc["points"][pts[i].first]["name"]);
    doc["pareto"][method] = front;
  }
  write_file_atomically(results / "speed_accuracy.svg", report::scatter_svg(speed));
  write_file_atomically(results / "memory_accuracy.svg", report::scatter_svg(memory));

  // Budget curves and knees.
  for (const auto& b : read_tsv(tsv / "budgets.tsv")) {
    if (b.size() < 3) continue;
    const std::string method = b[0];
    std::string param = b[1] == "input" ? "width" : b[1];
    report::ScatterChart chart;
    chart.x_label =
        param == "recon.max_gaussians" ? "Gaussians at the end (recon.gaussians)" : param;
    chart.y_label = headline[method];
    chart.join_series = true;
    std::vector<std::tuple<double, double, double, std::string>> curve;  // x, mean, std, value
    for (const auto& key : order) {
      const Point& p = points[key];
      if (p.kind != "budget" || p.method != method || p.param != param || p.metric.empty())
        continue;
      const auto [m, ms] = mean_std(p.metric);
      const double x = param == "recon.max_gaussians" && !p.gaussians.empty()
                           ? mean_std(p.gaussians).first
                           : std::stod(p.value);
      curve.emplace_back(x, m, ms, p.value);
    }
    if (curve.empty()) continue;
    std::sort(curve.begin(), curve.end());
    for (const auto& [x, m, ms, v] : curve) chart.points.push_back({x, 0, m, ms, v, v, 0});
    const auto best = *std::max_element(
        curve.begin(), curve.end(),
        [](const auto& a, const auto& c) { return std::get<1>(a) < std::get<1>(c); });
    std::string knee;
    for (const auto& [x, m, ms, v] : curve)
      if (m >= std::get<1>(best) - std::get<2>(best)) {
        knee = v;
        break;
      }
    doc["knees"].push_back({{"method", method},
                            {"param", param},
                            {"best", std::get<3>(best)},
                            {"best_mean", std::get<1>(best)},
                            {"best_std", std::get<2>(best)},
                            {"knee", knee}});
    std::string file = "budget_" + method + "_" + param + ".svg";
    std::replace(file.begin(), file.end(), '.', '_');
    file.replace(file.size() - 4, 4, ".svg");
    write_file_atomically(results / file, report::scatter_svg(chart));
  }
  write_file_atomically(results / "experiments.json", doc.dump(2) + "\n");
  std::cout << doc["pareto"].dump(2) << "\n" << doc["knees"].dump(2) << "\n";
  return 0;
}
