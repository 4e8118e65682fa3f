// The runs of compare_binaries.sh (one graph by two gslift binaries, alternated) as
// <name>.json and <name>.svg: per binary each round's wall time, peak memory and reconstruction
// phases (the splat.reconstruct node's *_seconds records), their medians, the ratio of the
// medians new / old, the machine, and whether every run wrote the same model.ply. Runs of
// bench_dtu_compare (compare_binaries.sh --dtu) instead give per resolution the seconds per step,
// the decoding phase and the steps alone, and whether every run reached the same held-out PSNR.
//   binary_compare_chart WORK_DIR RESULTS_DIR NAME
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/atomic_file.hpp"
#include "base/statistics.hpp"
#include "base/svg.hpp"
#include "bench/common/json_file.hpp"
#include "bench/common/tsv.hpp"

using namespace gslift;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// What is compared, in chart order: the run's wall time and peak memory, then the
// reconstruction's total and phases.
const std::vector<std::pair<std::string, std::string>> kMetrics = {
    {"wall_s", "whole run (s)"},
    {"recon_s", "reconstruction (s)"},
    {"render_seconds", "  render (s)"},
    {"losses_seconds", "  losses (s)"},
    {"backward_seconds", "  backward (s)"},
    {"density_seconds", "  density control (s)"},
    {"adam_seconds", "  Adam (s)"},
    {"held_out_poses_seconds", "  held-out poses (s)"},
    {"peak_rss_mb", "peak memory (MB)"}};

struct Run {
  std::map<std::string, double> values;
  std::string model;  // the reconstruction's model.ply bytes; DTU: its held-out PSNRs
  std::string git;
  // DTU runs: what `values` holds, in chart order (kMetrics for graph runs).
  std::vector<std::pair<std::string, std::string>> metrics;
};

std::string fixed(double v, int digits) {
  char b[32];
  std::snprintf(b, sizeof b, "%.*f", digits, v);
  return b;
}

std::string file_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A bench_dtu_compare run's dtu_compare.json: per resolution the seconds per step as the bench
// reports them (the reconstruction's time over its steps, decoding the photos included) and,
// where the binary reports its phases, the decoding (`prepare`) and the steps without it.
bool read_dtu_run(const json& report, Run& run) {
  if (!report.is_object() || !report.contains("runs") || report["runs"].empty()) return false;
  for (const json& r : report["runs"]) {
    const std::string size = std::to_string(r["resolution"][0].get<int>()) + "x" +
                             std::to_string(r["resolution"][1].get<int>());
    const double seconds = r.value("seconds", 0.0), steps = r.value("steps", 1);
    run.values["step_ms " + size] = 1000 * r.value("seconds_per_step", 0.0);
    run.metrics.emplace_back("step_ms " + size, size + ": per step (ms)");
    if (r.contains("phases") && r["phases"].contains("prepare")) {
      const double prepare = r["phases"]["prepare"].get<double>();
      run.values["prepare_s " + size] = prepare;
      run.values["steps_ms " + size] = 1000 * (seconds - prepare) / steps;
      run.metrics.emplace_back("prepare_s " + size, "  decoding photos (s)");
      run.metrics.emplace_back("steps_ms " + size, "  steps alone (ms)");
    }
    run.model += (run.model.empty() ? "" : "/") + fixed(r.value("test_psnr", 0.0), 4);
  }
  return true;
}

// The run in `dir`, or nothing when it did not finish.
bool read_run(const fs::path& dir, Run& run) {
  if (fs::exists(dir / "dtu_compare.json"))
    return read_dtu_run(bench::read_json_or_discarded(dir / "dtu_compare.json"), run);
  const json record = bench::read_json_or_discarded(dir / "run.json");
  if (!record.is_object() || record["run"].value("status", "") != "ok") return false;
  run.values["wall_s"] = record["run"].value("total_s", 0.0);
  run.values["peak_rss_mb"] = record["run"].value("peak_rss_mb", 0.0);
  run.git = record["gslift"].value("git", "");
  for (const auto& node : record["nodes"]) {
    if (node.value("type", "") != "splat.reconstruct") continue;
    const json& r = node["records"];
    run.values["recon_s"] = node.value("wall_s", 0.0);
    for (const auto& [key, label] : kMetrics)
      if (r.contains(key)) run.values[key] = r[key].get<double>();
    run.model = file_bytes(dir / node.value("id", "") / "model.ply");
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: binary_compare_chart WORK_DIR RESULTS_DIR NAME\n";
    return 2;
  }
  const fs::path work = argv[1], results = argv[2];
  const std::string name = argv[3];
  std::map<std::string, std::string> setup;
  for (const auto& row : bench::read_tsv(work / "setup.tsv"))
    if (row.size() >= 2) setup[row[0]] = row[1];
  const std::vector<std::string> labels = bench::split(setup["labels"], ',');
  const std::string old_label = labels.size() == 2 ? labels[0] : "old";
  const std::string new_label = labels.size() == 2 ? labels[1] : "new";
  std::map<std::string, std::vector<Run>> runs;
  std::vector<std::string> failed;
  int rounds = 0;
  for (int r = 1; fs::exists(work / ("old-" + std::to_string(r))); ++r) {
    rounds = r;
    for (const std::string which : {"old", "new"}) {
      Run run;
      const std::string dir = which + "-" + std::to_string(r);
      if (read_run(work / dir, run))
        runs[which].push_back(std::move(run));
      else
        failed.push_back(dir);
    }
  }
  if (runs["old"].empty() || runs["new"].empty()) {
    std::cerr << "binary_compare_chart: no finished run of "
              << (runs["old"].empty() ? "old" : "new") << " under " << work << "\n";
    return 1;
  }
  const bool dtu = !runs["new"].front().metrics.empty();
  bool identical = true;
  for (const auto& [which, list] : runs)
    for (const Run& run : list)
      identical &= !run.model.empty() && run.model == runs["old"].front().model;

  json out;
  out["benchmark"] = "one graph by two gslift binaries, alternated (compare_binaries.sh)";
  out["graph"] = setup["graph"];
  out["machine"] = setup["machine"];
  out["binaries"] = {
      {"old", {{"label", old_label}, {"path", setup["old"]}, {"git", runs["old"].front().git}}},
      {"new", {{"label", new_label}, {"path", setup["new"]}, {"git", runs["new"].front().git}}}};
  out["rounds"] = rounds;
  out["failed_runs"] = failed;
  out[dtu ? "identical_psnr" : "identical_models"] = identical;
  if (dtu)  // per resolution, 400x300 first
    out["held_out_psnr"] = {{"old", runs["old"].front().model}, {"new", runs["new"].front().model}};
  struct Row {
    std::string label;
    double old_median, new_median;
  };
  std::vector<Row> rows;
  // Seconds per step where an old binary does not report its phases: only what both report.
  for (const auto& [key, label] : dtu ? runs["new"].front().metrics : kMetrics) {
    std::map<std::string, std::vector<double>> values;
    for (const auto& [which, list] : runs)
      for (const Run& run : list)
        if (run.values.count(key)) values[which].push_back(run.values.at(key));
    if (values["old"].empty() || values["new"].empty()) continue;
    const double o = median(values["old"]), n = median(values["new"]);
    out["metrics"].push_back({{"name", key},
                              {"old", values["old"]},
                              {"new", values["new"]},
                              {"old_median", o},
                              {"new_median", n},
                              {"ratio", o > 0 ? n / o : 0.0}});
    rows.push_back({label, o, n});
    std::cout << label << ": " << fixed(o, dtu ? 2 : 1) << " -> " << fixed(n, dtu ? 2 : 1) << " ("
              << fixed(o > 0 ? n / o : 0.0, dtu ? 3 : 2) << "x)\n";
  }

  // Horizontal bars: per metric the old median (grey) over the new one (blue), each against the
  // larger of the two, the ratio at the right.
  const double left = 160, bar_width = 360, row_height = 34, top = 48;
  Svg svg(left + bar_width + 150, top + row_height * rows.size() + 30, 12, true);
  svg.text(10, 18,
           name + ": " + setup["graph"] + ", medians of " + std::to_string(rounds) +
               " alternated rounds",
           "font-weight='bold'");
  svg.text(10, 36,
           setup["machine"] + "; grey " + old_label + ", blue " + new_label +
               (dtu ? "; PSNR " + runs["old"].front().model + " -> " + runs["new"].front().model
                    : (identical ? "; every model.ply identical" : "; models differ")));
  for (size_t i = 0; i < rows.size(); ++i) {
    const Row& row = rows[i];
    const double y = top + row_height * i,
                 scale = bar_width / std::max(row.old_median, row.new_median);
    svg.text(10, y + 20, row.label);
    svg.rect(left, y + 4, row.old_median * scale, 12, "#9e9e9e");
    svg.rect(left, y + 17, row.new_median * scale, 12, "#3b73b9");
    svg.text(left + row.old_median * scale + 4, y + 14, fixed(row.old_median, 1), "font-size='10'");
    svg.text(left + row.new_median * scale + 4, y + 27, fixed(row.new_median, 1), "font-size='10'");
    svg.text(left + bar_width + 60, y + 20,
             fixed(row.old_median > 0 ? row.new_median / row.old_median : 0.0, 2) + "x");
  }
  write_file_atomically(results / (name + ".json"), out.dump(2) + "\n");
  write_file_atomically(results / (name + ".svg"), svg.str());
  std::cout << "wrote " << (results / (name + ".json")).string() << " and .svg\n";
  return failed.empty() ? 0 : 1;
}
