// Issue 11's levers on one chart: every variant of bench/results/hidden_levers.csv measured over
// the five seeds, held-out floaters against holes on covered pixels (the two targets that trade
// against each other), with the mean, median and standard deviation of each figure in a JSON.
//   heldout_levers_chart bench/results/hidden_levers.csv bench/results
// writes hidden_levers.json and hidden_levers.svg into the results folder.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/atomic_file.hpp"
#include "base/statistics.hpp"
#include "bench/common/csv_line.hpp"
#include "report/charts.hpp"

using namespace gslift;
using bench::csv_fields;
using nlohmann::json;

namespace {

// The figures summarised per variant: CSV column, name in the JSON, scale (fractions to %).
struct Figure {
  const char* column;
  const char* name;
  double scale;
};
const Figure kFigures[] = {{"test_floaters", "floaters_pct", 100},
                           {"test_floaters_away_from_discontinuity", "floaters_away_pct", 100},
                           {"test_holes_covered", "holes_covered_pct", 100},
                           {"test_psnr", "heldout_psnr_db", 1},
                           {"train_psnr", "train_psnr_db", 1},
                           {"gaussians", "gaussians", 1},
                           {"mIoU", "mIoU", 1},
                           {"mLocAcc", "mLocAcc", 1},
                           {"mAcc", "mAcc", 1}};

// The variant that is langor.yaml now (its label in the CSV says so).
bool is_default(const std::string& variant) {
  return variant.find("(langor.yaml)") != std::string::npos;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: heldout_levers_chart HIDDEN_LEVERS_CSV RESULTS_DIR\n";
    return 2;
  }
  std::ifstream in(argv[1]);
  if (!in) {
    std::cerr << "heldout_levers_chart: cannot read " << argv[1] << "\n";
    return 4;
  }
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = csv_fields(line);
  std::map<std::string, size_t> column;
  for (size_t i = 0; i < header.size(); ++i) column[header[i]] = i;
  for (const char* needed : {"variant", "seed", "test_floaters", "test_holes_covered"})
    if (!column.count(needed)) {
      std::cerr << "heldout_levers_chart: " << argv[1] << " has no column '" << needed << "'\n";
      return 4;
    }

  // Per variant (in the file's order), per figure, the values over its runs.
  std::vector<std::string> order;
  std::map<std::string, std::map<std::string, std::vector<double>>> values;
  while (std::getline(in, line)) {
    const std::vector<std::string> f = csv_fields(line);
    if (f.size() != header.size()) continue;
    const std::string& variant = f[column["variant"]];
    if (!values.count(variant)) order.push_back(variant);
    for (const Figure& fig : kFigures) {
      const auto c = column.find(fig.column);
      if (c == column.end() || f[c->second].empty()) continue;
      values[variant][fig.name].push_back(std::stod(f[c->second]) * fig.scale);
    }
  }

  json doc = {{"benchmark", "hidden_levers"},
              {"source", "bench/results/hidden_levers.csv (bench/splat_recon/README.md)"},
              {"capture", "embedded:or?seed=S, default preset, held-out view cam_04"},
              {"targets",
               {{"floaters_pct", "< 1"},
                {"holes_covered_pct", "< 2"},
                {"heldout_psnr_db", ">= 18"},
                {"train_psnr_db", ">= 29"}}},
              {"variants", json::array()}};
  report::ScatterChart chart;
  chart.x_label = "holes on covered pixels, held-out view (%)";
  chart.y_label = "floater pixels, held-out view (%)";
  chart.series_names = {"a lever measured over seeds 0-4", "langor.yaml", "the targets' corner"};
  chart.pareto = true;
  chart.lower_y_is_better = true;
  int index = 0;
  for (const std::string& variant : order) {
    ++index;
    json v = {{"index", index}, {"variant", variant}};
    for (const auto& [name, series] : values[variant]) {
      const auto [mean, std] = mean_std(series);
      v[name] = {{"n", series.size()}, {"mean", mean}, {"median", median(series)}, {"std", std}};
    }
    doc["variants"].push_back(v);
    const auto& fl = values[variant]["floaters_pct"];
    const auto& holes = values[variant]["holes_covered_pct"];
    if (fl.size() != 5 || holes.size() != 5) continue;  // five seeds only: comparable means
    const auto [x, x_err] = mean_std(holes);
    const auto [y, y_err] = mean_std(fl);
    chart.points.push_back(
        {x, x_err, y, y_err, variant, std::to_string(index), is_default(variant) ? 1 : 0});
  }
  chart.points.push_back(
      {2, 0, 1, 0, "targets: holes on covered pixels < 2%, floaters < 1%", "", 2});
  const std::filesystem::path results = argv[2];
  write_file_atomically(results / "hidden_levers.svg", report::scatter_svg(chart));
  write_file_atomically(results / "hidden_levers.json", doc.dump(2) + "\n");
  std::cout << "hidden_levers: " << order.size() << " variants -> "
            << (results / "hidden_levers.json").string() << ", hidden_levers.svg\n";
  return 0;
}
