// The results of a table of sweeps (bench/protocol/run.sh): the dev/test protocol (issue 28,
// protocol.tsv) or a method's ablations (bench/langor/langor.tsv, ...), from the sweeps' folders:
//  - <table>.json: per line (method or variant, and set) the headline metric over its rooms (mean,
//    std, min, max, each room's value), the headline node's other records (means), the mean of
//    every other record of the graph (per-view and per-item ones left out), failed rooms, the
//    median time and peak memory of a room and the median wall time of each node; and the paired
//    comparisons of the pairs.tsv beside the table: first minus second, room by room (the same
//    capture and seed), with the mean's 95% t interval; a room a line runs several times (a
//    `--grid` in its sweep arguments) has the mean of those runs;
//  - <table>.svg: per line a dev bar and a test bar (mean, whiskers one std), each room a dot;
//  - a markdown table on stdout, as the READMEs show it.
// A line with no sweep folder under SWEEPS_DIR keeps the set <table>.json already holds for it.
//   protocol_chart SWEEPS_DIR TABLE.tsv RESULTS_DIR   (TABLE a folder: its protocol.tsv)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/atomic_file.hpp"
#include "base/statistics.hpp"
#include "base/svg.hpp"
#include "bench/common/json_file.hpp"
#include "bench/common/tsv.hpp"

using namespace gslift;
using bench::read_json_or_discarded;
using bench::read_tsv;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// One method on one set: its rooms' headline values, keyed by (capture, seed) for pairing.
struct SetResult {
  std::string method, set, graph, headline;
  std::map<std::pair<std::string, uint64_t>, double> rooms;
  std::map<std::string, std::vector<double>> others;   // the headline node's other records
  std::map<std::string, std::vector<double>> records;  // every record but per-view/item ones
  std::map<std::string, std::vector<double>> node_s;   // wall time per node
  std::vector<double> times, peak_mb;
  int failed = 0;
  std::vector<std::string> errors;
};

SetResult read_set(const fs::path& dir, const std::vector<std::string>& row) {
  SetResult r{row[0], row[1], row[2], row[3], {}, {}, {}, {}, {}, {}, 0, {}};
  const json sweep = read_json_or_discarded(dir / "sweep.json");
  if (!sweep.is_object()) return r;
  const std::string node = r.headline.substr(0, r.headline.find('.') + 1);
  // A room with several runs (a line's `--grid`, e.g. prompt.only over the instances: one click
  // at a time) is scored by their mean.
  std::map<std::pair<std::string, uint64_t>, std::pair<double, int>> per_room;
  for (const auto& run : sweep["runs"]) {
    if (run["status"] != "ok") {
      ++r.failed;
      r.errors.push_back(run.value("error", json("")).is_string() ? run["error"].get<std::string>()
                                                                  : std::string());
      continue;
    }
    const auto& metrics = run["metrics"];
    if (!metrics.contains(r.headline)) continue;
    const std::string input = run["input"].is_string() ? run["input"].get<std::string>() : "";
    auto& [sum, runs] = per_room[{input, run["seed"].get<uint64_t>()}];
    sum += metrics[r.headline].get<double>();
    ++runs;
    for (const auto& [k, v] : metrics.items())
      if (k.rfind(node, 0) == 0 && k != r.headline && k.find('/') == std::string::npos)
        r.others[k.substr(node.size())].push_back(v.get<double>());
    // One level of '/' at most: train/CA and recall/<class> stay, per-view and per-item records
    // (view/<name>/CA, growth/<k>/kept) would bury them.
    for (const auto& [k, v] : metrics.items())
      if (std::count(k.begin(), k.end(), '/') <= 1) r.records[k].push_back(v.get<double>());
    if (run.contains("node_wall_s"))
      for (const auto& [k, v] : run["node_wall_s"].items()) r.node_s[k].push_back(v.get<double>());
    r.times.push_back(run["total_s"].get<double>());
    r.peak_mb.push_back(run["peak_rss_mb"].get<double>());
  }
  for (const auto& [room, sum_runs] : per_room) r.rooms[room] = sum_runs.first / sum_runs.second;
  return r;
}

// A line whose sweep folder is absent here keeps what the table's results file already holds for
// it (a refresh of some lines on a machine without the others' sweeps): its rooms, the means of
// its records and its medians, each a one-value list so that the means and medians stand.
SetResult stored_set(const json& stored, const std::vector<std::string>& row) {
  SetResult r{row[0], row[1], row[2], row[3], {}, {}, {}, {}, {}, {}, 0, {}};
  if (!stored.is_object() || !stored.contains("sets")) return r;
  for (const auto& s : stored["sets"]) {
    if (s.value("method", "") != r.method || s.value("set", "") != r.set ||
        s.value("graph", "") != r.graph || s.value("headline", "") != r.headline)
      continue;
    for (const auto& room : s["rooms"])
      r.rooms[{room["input"].get<std::string>(), room["seed"].get<uint64_t>()}] =
          room["value"].get<double>();
    for (const auto& [k, v] : s["others"].items()) r.others[k] = {v.get<double>()};
    for (const auto& [k, v] : s["records"].items()) r.records[k] = {v.get<double>()};
    for (const auto& [k, v] : s["median_node_s"].items()) r.node_s[k] = {v.get<double>()};
    if (s["median_time_s"].is_number()) r.times = {s["median_time_s"].get<double>()};
    if (s["median_peak_mb"].is_number()) r.peak_mb = {s["median_peak_mb"].get<double>()};
    r.failed = s.value("failed", 0);
    r.errors = s.value("errors", std::vector<std::string>{});
  }
  return r;
}

std::vector<double> values(const SetResult& r) {
  std::vector<double> v;
  for (const auto& [room, x] : r.rooms) v.push_back(x);
  return v;
}

std::string fixed(double x, int decimals = 1) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, x);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: protocol_chart SWEEPS_DIR TABLE.tsv RESULTS_DIR\n";
    return 2;
  }
  const fs::path dir = argv[1], results = argv[3];
  // A folder is the protocol's (its protocol.tsv): how run.sh called this before tables.
  const fs::path table = fs::is_directory(argv[2]) ? fs::path(argv[2]) / "protocol.tsv" : argv[2];
  const std::string stem = table.stem().string();
  const json stored = read_json_or_discarded(results / (stem + ".json"));
  std::vector<SetResult> sets;
  for (const auto& row : read_tsv(table)) {
    if (row.size() < 5) continue;
    const fs::path sweep = dir / (row[0] + "_" + row[1]);
    SetResult r = fs::exists(sweep / "sweep.json") ? read_set(sweep, row) : stored_set(stored, row);
    if (!r.rooms.empty() || r.failed > 0) sets.push_back(std::move(r));
  }
  if (sets.empty()) {
    std::cerr << "protocol_chart: no finished sweep under " << dir << "\n";
    return 1;
  }
  const auto find = [&](const std::string& method, const std::string& set) -> const SetResult* {
    for (const auto& s : sets)
      if (s.method == method && s.set == set) return &s;
    return nullptr;
  };

  json out_sets = json::array();
  std::cout << "| method | set | rooms | headline | mean +- std | min - max | other records "
               "(means) | time per room (median) |\n|---|---|---|---|---|---|---|---|\n";
  for (const auto& s : sets) {
    const auto v = values(s);
    const auto [mean, sd] = mean_std(v);
    json others = json::object(), rooms = json::array(), records = json::object(),
         node_s = json::object();
    for (const auto& [k, xs] : s.records) records[k] = mean_std(xs).first;
    for (const auto& [k, xs] : s.node_s) node_s[k] = median(xs);
    std::string other_text;
    for (const auto& [k, xs] : s.others) {
      others[k] = mean_std(xs).first;
      other_text += (other_text.empty() ? "" : ", ") + k + " " + fixed(mean_std(xs).first);
    }
    for (const auto& [room, x] : s.rooms)
      rooms.push_back({{"input", room.first}, {"seed", room.second}, {"value", x}});
    const double lo = v.empty() ? NAN : *std::min_element(v.begin(), v.end());
    const double hi = v.empty() ? NAN : *std::max_element(v.begin(), v.end());
    out_sets.push_back({{"method", s.method},
                        {"set", s.set},
                        {"graph", s.graph},
                        {"headline", s.headline},
                        {"n", v.size()},
                        {"failed", s.failed},
                        {"errors", s.errors},
                        {"mean", mean},
                        {"std", sd},
                        {"min", lo},
                        {"max", hi},
                        {"others", others},
                        {"median_time_s", median(s.times)},
                        {"median_peak_mb", median(s.peak_mb)},
                        {"median_node_s", node_s},
                        {"records", records},
                        {"rooms", rooms}});
    std::cout << "| " << s.method << " | " << s.set << " | " << v.size()
              << (s.failed ? " (" + std::to_string(s.failed) + " failed)" : std::string()) << " | "
              << s.headline << " | " << fixed(mean) << " +- " << fixed(sd) << " | " << fixed(lo)
              << " - " << fixed(hi) << " | " << other_text << " | " << fixed(median(s.times), 0)
              << " s |\n";
  }

  json out_pairs = json::array();
  for (const auto& row : read_tsv(table.parent_path() / "pairs.tsv")) {  // none: no file
    if (row.size() < 3) continue;
    const SetResult *a = find(row[0], row[2]), *b = find(row[1], row[2]);
    if (!a || !b) continue;
    std::vector<double> diffs;
    int wins = 0;
    for (const auto& [room, x] : a->rooms) {
      auto it = b->rooms.find(room);
      if (it == b->rooms.end()) continue;
      diffs.push_back(x - it->second);
      wins += x > it->second;
    }
    const MeanInterval m = mean_interval_95(diffs);
    out_pairs.push_back({{"first", row[0]},
                         {"second", row[1]},
                         {"set", row[2]},
                         {"metric", a->headline},
                         {"n", m.n},
                         {"first_wins", wins},
                         {"mean", m.mean},
                         {"low", std::isfinite(m.low) ? json(m.low) : json()},
                         {"high", std::isfinite(m.high) ? json(m.high) : json()}});
    std::cout << "\npaired, " << row[0] << " minus " << row[1] << " on " << row[2] << " ("
              << a->headline << ", " << m.n << " rooms, first higher in " << wins
              << "): " << fixed(m.mean, 2) << " [" << fixed(m.low, 2) << ", " << fixed(m.high, 2)
              << "]\n";
  }

  // The chart: per method its sets' bars side by side in the table's order (dev sets, then test),
  // whiskers one std, a dot per room.
  std::vector<std::string> methods;
  size_t most_sets = 2;
  for (const auto& s : sets) {
    if (std::find(methods.begin(), methods.end(), s.method) == methods.end())
      methods.push_back(s.method);
    most_sets = std::max<size_t>(
        most_sets, std::count_if(sets.begin(), sets.end(),
                                 [&](const SetResult& o) { return o.method == s.method; }));
  }
  const double group_w = 50 * static_cast<double>(most_sets) + 30, left = 50, top = 40,
               plot_h = 260;
  const double width = std::max(620.0, left + group_w * static_cast<double>(methods.size()) + 20);
  Svg svg(width, top + plot_h + 70, 12, true);
  svg.text(left, 20,
           (stem == "protocol" ? std::string("Headline metric per method")
                               : stem + ": " + sets.front().headline + " per variant") +
               ": dev rooms (settings chosen there) | test rooms",
           "font-weight='bold'");
  const auto y_of = [&](double v) { return top + plot_h * (1 - std::clamp(v, 0.0, 100.0) / 100); };
  for (int t = 0; t <= 100; t += 20) {
    svg.line(left, y_of(t), width - 20, y_of(t), "#ddd");
    svg.text(left - 6, y_of(t) + 4, std::to_string(t), "text-anchor='end'");
  }
  for (size_t m = 0; m < methods.size(); ++m) {
    const double x0 = left + group_w * static_cast<double>(m) + 15;
    int slot = 0;
    for (const SetResult& set : sets) {
      if (set.method != methods[m]) continue;
      const SetResult* s = &set;
      const double x = x0 + 50 * slot++;
      const auto v = values(*s);
      const auto [mean, sd] = mean_std(v);
      const std::string colour = s->set == "test" ? "#3182bd" : "#9ecae1";
      svg.begin_group(s->method + " " + s->set + ": " + s->headline + " " + fixed(mean) + " +- " +
                      fixed(sd) + " over " + std::to_string(v.size()) + " rooms");
      svg.rect(x, y_of(mean), 40, y_of(0) - y_of(mean), colour);
      svg.line(x + 20, y_of(mean - sd), x + 20, y_of(mean + sd), "black");
      for (size_t i = 0; i < v.size(); ++i)
        svg.circle(x + 8 + 24.0 * static_cast<double>(i % 7) / 6, y_of(v[i]), 2, "#222");
      svg.text(x + 20, y_of(mean + sd) - 4, fixed(mean), "text-anchor='middle'");
      svg.text(x + 20, y_of(0) + 14, s->set, "text-anchor='middle' font-size='10'");
      svg.end_group();
    }
    svg.text(x0 + 25 * slot - 5, y_of(0) + 32, methods[m], "text-anchor='middle'");
  }
  svg.text(
      left, top + plot_h + 60,
      "bars: mean over rooms, whiskers: one std, dots: rooms; every record in " + stem + ".json",
      "font-size='10'");
  write_file_atomically(results / (stem + ".svg"), svg.str());
  write_file_atomically(
      results / (stem + ".json"),
      json({{"table", table.generic_string()}, {"sets", out_sets}, {"pairs", out_pairs}}).dump(1) +
          "\n");
  std::cout << "\nwrote " << (results / (stem + ".json")).string() << " and " << stem << ".svg\n";
  return 0;
}
