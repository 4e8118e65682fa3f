// Two instance-segmentation sweeps over the same rooms, compared per ground-truth class: where one
// method wins or loses (issue 28's "find out why, per room, per class"). Reads each ok run's
// <node>/matches.csv (eval.instance_hungarian: per ground-truth instance its class and matched
// IoU) and pairs the instances of the two sweeps by (capture, seed, instance id). Per class:
// instances paired, mean matched IoU of each method, the paired difference (first minus second)
// with its mean's 95% t interval, and the share of instances each matches at IoU > 0.5 (a hit, as
// Gaga's precision and recall count them). Writes
//  - <stem>.json: the classes, ordered by the difference, and the rooms left out;
//  - <stem>.svg: per class the two means, and the difference with its interval;
//  - a markdown table on stdout, as the READMEs show it.
//   class_breakdown SWEEP_A SWEEP_B NODE NAME_A NAME_B OUT_STEM
// SWEEP: a sweep folder, or FOLDER@PARAM=VALUE[,...] for one point of a `--grid` sweep.
// e.g. class_breakdown build/protocol/protosaga_test build/protocol/gaga_test eval Proto-SaGa Gaga
//      bench/results/protosaga_gaga_classes
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/atomic_file.hpp"
#include "base/statistics.hpp"
#include "base/svg.hpp"
#include "bench/common/csv_line.hpp"
#include "bench/common/json_file.hpp"

using namespace gslift;
using bench::csv_fields;
using bench::read_json_or_discarded;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

using InstanceKey = std::tuple<std::string, uint64_t, int>;  // capture, seed, instance id
struct Instance {
  std::string cls;
  double iou = 0;
};

// The instances of every ok run of a sweep with a class (label 0 and unnamed instances are left
// out); `missing` gets the runs that did not finish or lack the node's matches.csv. `spec` is
// DIR, or DIR@PARAM=VALUE[,PARAM=VALUE...] for the runs of one grid point of a `--grid` sweep
// (their sweep.json `params`).
std::map<InstanceKey, Instance> read_sweep(const std::string& spec, const std::string& node,
                                           std::vector<std::string>& missing) {
  const fs::path dir = spec.substr(0, spec.find('@'));
  std::map<std::string, std::string> point;
  if (spec.find('@') != std::string::npos) {
    std::stringstream pairs(spec.substr(spec.find('@') + 1));
    for (std::string pair; std::getline(pairs, pair, ',');) {
      if (pair.find('=') == std::string::npos)
        throw std::runtime_error(spec + ": expected PARAM=VALUE after @, got '" + pair + "'");
      point[pair.substr(0, pair.find('='))] = pair.substr(pair.find('=') + 1);
    }
  }
  const json sweep = read_json_or_discarded(dir / "sweep.json");
  if (!sweep.is_object() || !sweep.contains("runs"))
    throw std::runtime_error(dir.string() + ": no sweep.json");
  std::map<InstanceKey, Instance> out;
  size_t selected = 0;
  for (const auto& run : sweep["runs"]) {
    const json params = run.value("params", json::object());
    if (!std::all_of(point.begin(), point.end(), [&](const auto& kv) {
          return params.contains(kv.first) && params[kv.first].is_string() &&
                 params[kv.first].template get<std::string>() == kv.second;
        }))
      continue;
    ++selected;
    const std::string input = run.value("input", std::string());
    const uint64_t seed = run.value("seed", uint64_t(0));
    const std::string name = input + " seed " + std::to_string(seed);
    std::ifstream in(dir / run.value("dir", std::string()) / node / "matches.csv");
    if (run.value("status", std::string()) != "ok" || !in) {
      missing.push_back(dir.filename().string() + ": " + name);
      continue;
    }
    std::string line;
    std::getline(in, line);
    const std::vector<std::string> header = csv_fields(line);
    const auto column = [&](const std::string& c) {
      const auto at = std::find(header.begin(), header.end(), c);
      if (at == header.end())
        throw std::runtime_error(dir.string() + ": " + name + ": matches.csv has no column " + c +
                                 " (written before eval named classes: rerun the sweep)");
      return size_t(at - header.begin());
    };
    const size_t id_col = column("gt_label"), class_col = column("class"), iou_col = column("iou");
    while (std::getline(in, line)) {
      const std::vector<std::string> f = csv_fields(line);
      if (f.size() != header.size() || f[class_col].empty()) continue;
      const InstanceKey key{input, seed, std::stoi(f[id_col])};
      if (out.count(key))
        throw std::runtime_error(
            dir.string() + ": " + name +
            " has several runs (a --grid sweep): select one with @PARAM=VALUE");
      out[key] = {f[class_col], std::stod(f[iou_col])};
    }
  }
  if (selected == 0) throw std::runtime_error(spec + ": no run matches");
  return out;
}

struct ClassRow {
  std::string cls;
  std::vector<double> a, b, diff;
  std::vector<std::string> rooms;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 7) {
    std::fprintf(stderr, "usage: class_breakdown SWEEP_A SWEEP_B NODE NAME_A NAME_B OUT_STEM\n");
    return 2;
  }
  const std::string node = argv[3], name_a = argv[4], name_b = argv[5];
  const fs::path stem = argv[6];
  std::vector<std::string> missing;
  std::map<InstanceKey, Instance> a, b;
  try {
    a = read_sweep(argv[1], node, missing);
    b = read_sweep(argv[2], node, missing);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "class_breakdown: %s\n", e.what());
    return 1;
  }
  std::map<std::string, ClassRow> classes;
  std::vector<double> all_a, all_b, all_diff;
  for (const auto& [key, ia] : a) {
    const auto ib = b.find(key);
    if (ib == b.end()) continue;  // a room only one sweep finished: listed in `missing`
    ClassRow& row = classes[ia.cls];
    row.cls = ia.cls;
    row.a.push_back(100 * ia.iou);
    row.b.push_back(100 * ib->second.iou);
    row.diff.push_back(100 * (ia.iou - ib->second.iou));
    all_a.push_back(100 * ia.iou);
    all_b.push_back(100 * ib->second.iou);
    all_diff.push_back(100 * (ia.iou - ib->second.iou));
  }
  if (classes.empty()) {
    std::fprintf(stderr, "class_breakdown: no instance with a class in both sweeps\n");
    return 1;
  }
  const auto hit_share = [](const std::vector<double>& v) {
    return 100.0 * double(std::count_if(v.begin(), v.end(), [](double x) { return x > 50; })) /
           double(v.size());
  };
  std::vector<ClassRow> rows;
  for (auto& [name, row] : classes) rows.push_back(std::move(row));
  std::sort(rows.begin(), rows.end(), [](const ClassRow& x, const ClassRow& y) {
    return mean_std(x.diff).first < mean_std(y.diff).first;
  });

  json out = {{"first", name_a},
              {"second", name_b},
              {"node", node},
              {"sweeps", {argv[1], argv[2]}},
              {"missing_runs", missing}};
  const auto summary = [&](const std::string& cls, const std::vector<double>& va,
                           const std::vector<double>& vb, const std::vector<double>& vd) {
    const MeanInterval d = mean_interval_95(vd);
    return json{{"class", cls},
                {"instances", va.size()},
                {"mean_first", mean_std(va).first},
                {"mean_second", mean_std(vb).first},
                {"difference", d.mean},
                {"difference_low", d.low},
                {"difference_high", d.high},
                {"hits_first", hit_share(va)},
                {"hits_second", hit_share(vb)}};
  };
  std::printf(
      "| class | instances | %s IoU | %s IoU | paired difference (95%%) | %s / %s IoU > 0.5 |\n"
      "| --- | ---: | ---: | ---: | ---: | ---: |\n",
      name_a.c_str(), name_b.c_str(), name_a.c_str(), name_b.c_str());
  const auto print_row = [](const json& r) {
    const double lo = r["difference_low"], hi = r["difference_high"];
    char interval[64] = "one instance";
    if (std::isfinite(lo) && std::isfinite(hi))
      std::snprintf(interval, sizeof interval, "%+.1f to %+.1f", lo, hi);
    std::printf("| %s | %zu | %.1f | %.1f | %+.1f (%s) | %.0f%% / %.0f%% |\n",
                r["class"].get<std::string>().c_str(), r["instances"].get<size_t>(),
                r["mean_first"].get<double>(), r["mean_second"].get<double>(),
                r["difference"].get<double>(), interval, r["hits_first"].get<double>(),
                r["hits_second"].get<double>());
  };

  for (const ClassRow& row : rows) {
    out["classes"].push_back(summary(row.cls, row.a, row.b, row.diff));
    print_row(out["classes"].back());
  }
  out["all"] = summary("all instances", all_a, all_b, all_diff);
  print_row(out["all"]);
  for (const std::string& m : missing)
    std::printf("left out (not finished in both): %s\n", m.c_str());

  // Chart: a row per class, the two means as bars on 0..100 and the difference with its interval
  // on a symmetric axis to the right.
  const double row_h = 22, label_w = 170, bar_w = 260, gap = 40, diff_w = 220, top = 40;
  const double height = top + row_h * double(rows.size()) + 40;
  Svg svg(label_w + bar_w + gap + diff_w + 20, height, 12, true);
  svg.text(10, 18,
           name_a + " (blue) against " + name_b + " (grey): mean matched IoU per class; " +
               "right: the paired difference, 95% interval");
  double span = 5;
  for (const json& r : out["classes"])
    span = std::max({span, std::fabs(r["difference_low"].get<double>()),
                     std::fabs(r["difference_high"].get<double>())});
  const double diff_x0 = label_w + bar_w + gap, diff_mid = diff_x0 + diff_w / 2;
  const auto diff_x = [&](double d) { return diff_mid + d / span * (diff_w / 2); };
  svg.line(diff_mid, top - 6, diff_mid, height - 30, "#888");
  svg.text(diff_x0, height - 14, Svg::number(-std::round(span)));
  svg.text(diff_x0 + diff_w - 20, height - 14, "+" + Svg::number(std::round(span)));
  svg.text(label_w, height - 14, "0");
  svg.text(label_w + bar_w - 20, height - 14, "100");
  for (size_t i = 0; i < rows.size(); ++i) {
    const json& r = out["classes"][i];
    const double y = top + row_h * double(i);
    svg.text(
        10, y + 12,
        r["class"].get<std::string>() + " (" + std::to_string(r["instances"].get<size_t>()) + ")");
    svg.rect(label_w, y + 1, bar_w * r["mean_first"].get<double>() / 100, 8, "#3465a4");
    svg.rect(label_w, y + 10, bar_w * r["mean_second"].get<double>() / 100, 8, "#999");
    const double lo = r["difference_low"], hi = r["difference_high"];
    if (std::isfinite(lo) && std::isfinite(hi))
      svg.line(diff_x(lo), y + 9, diff_x(hi), y + 9, "#333");
    svg.circle(diff_x(r["difference"].get<double>()), y + 9, 3.5,
               r["difference"].get<double>() < 0 ? "#cc0000" : "#3465a4");
  }
  try {
    write_file_atomically(stem.string() + ".json", out.dump(1) + "\n");
    write_file_atomically(stem.string() + ".svg", svg.str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "class_breakdown: %s\n", e.what());
    return 1;
  }
  return 0;
}
