// The stability matrix (issue 15) from the sweeps bench/stability/run.sh ran: for every method and
// failure knob it applies to, the headline metric's mean +- std over seeds at each level, the
// count of crashes (a run killed by a signal) and of runs that ended with an error, and the
// cliffs: neighbouring levels whose means differ by more than the larger of their two seed
// standard deviations. Writes <results>/stability.json, stability.md (the README's table) and
// stability_<method>.svg (a heat map per method).
//   stability_matrix SWEEPS_DIR METHODS.tsv KNOBS.tsv RESULTS_DIR
// A method's runs are those of SWEEPS_DIR/<method>/sweep.json and of every <method>@*/sweep.json.
#include <algorithm>
#include <cmath>
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
#include "bench/common/tsv.hpp"

using namespace gslift;
using bench::read_tsv;
using bench::split;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// "embedded:or?seed=1&width=240&height=180&depth_noise=0.05" -> {seed: 1, ..., depth_noise: 0.05}
std::map<std::string, std::string> spec_settings(const std::string& spec) {
  std::map<std::string, std::string> out;
  const auto q = spec.find('?');
  if (q == std::string::npos) return out;
  for (const auto& item : split(spec.substr(q + 1), '&')) {
    const auto eq = item.find('=');
    if (eq != std::string::npos) out[item.substr(0, eq)] = item.substr(eq + 1);
  }
  return out;
}

struct Knob {
  std::string name, group;
  std::vector<std::string> levels;
};

struct Cell {
  std::vector<double> values;
  int crashes = 0, errors = 0, runs = 0;
  std::vector<std::string> messages;
};

std::string fixed(double v, int digits = 1) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

// Red (0) -> yellow (50) -> green (100) for a metric in percent.
std::string colour(double v) {
  const double t = std::clamp(v / 100.0, 0.0, 1.0);
  const int r = t < 0.5 ? 230 : int(230 - (t - 0.5) * 2 * 150);
  const int g = t < 0.5 ? int(80 + t * 2 * 130) : 210;
  char buf[16];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", r, g, 90);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::cerr << "usage: stability_matrix SWEEPS_DIR METHODS.tsv KNOBS.tsv RESULTS_DIR\n";
    return 2;
  }
  const fs::path sweeps = argv[1], results = argv[4];
  std::vector<Knob> knobs;
  for (const auto& row : read_tsv(argv[3]))
    if (row.size() >= 3) knobs.push_back({row[0], row[1], split(row[2], ',')});

  json doc = {{"benchmark", "stability"},
              {"setting",
               "embedded OR 240x180, the methods' shortened settings (bench/experiments/"
               "methods.tsv), one knob changed at a time from the default capture"},
              {"methods", json::array()}};
  std::string md;
  int total_crashes = 0, total_errors = 0;
  for (const auto& m : read_tsv(argv[2])) {
    if (m.size() < 4) continue;
    const std::string name = m[0], headline = m[2];
    const std::vector<std::string> inputs = split(m[3], ',');
    // A method's runs: the sweep <name> and any later one of a few knobs, <name>@<knobs>.
    std::vector<fs::path> sweep_files;
    for (const auto& e : fs::directory_iterator(sweeps)) {
      const std::string folder = e.path().filename().string();
      if ((folder == name || folder.rfind(name + "@", 0) == 0) &&
          fs::exists(e.path() / "sweep.json"))
        sweep_files.push_back(e.path() / "sweep.json");
    }
    std::sort(sweep_files.begin(), sweep_files.end());
    if (sweep_files.empty()) {
      std::cerr << "stability: no sweep of " << name << " in " << sweeps << ", method skipped\n";
      continue;
    }
    json runs = json::array();
    for (const auto& f : sweep_files) {
      json sweep;
      std::ifstream(f) >> sweep;
      for (const auto& run : sweep["runs"]) runs.push_back(run);
    }
    // knob -> level -> cell
    std::map<std::string, std::map<std::string, Cell>> cells;
    for (const auto& run : runs) {
      // A run stopped from outside (the sweep was interrupted) says nothing about the method.
      if (run["status"] == "interrupted") continue;
      const auto settings = spec_settings(run["params"].value("input", std::string()));
      for (const auto& k : knobs) {
        auto it = settings.find(k.name);
        if (it == settings.end()) continue;
        Cell& c = cells[k.name][it->second];
        ++c.runs;
        if (run["status"] == "ok" && run["metrics"].contains(headline)) {
          c.values.push_back(run["metrics"][headline].get<double>());
        } else {
          const std::string error = run["error"].is_string() ? run["error"].get<std::string>() : "";
          (error.rfind("killed by signal", 0) == 0 ? c.crashes : c.errors)++;
          if (c.messages.size() < 2) c.messages.push_back(error);
        }
      }
    }
    json mj = {{"method", name},
               {"headline", headline},
               {"knobs", json::array()},
               {"cliffs", json::array()}};
    md += "\n**" + name + "** (" + headline +
          ", mean ± std over seeds; runs that crashed / "
          "ended with an error)\n\n| knob | levels |\n|---|---|\n";
    int crashes = 0, errors = 0;
    std::vector<const Knob*> shown;
    for (const auto& k : knobs) {
      const bool applies = std::find(inputs.begin(), inputs.end(), k.group) != inputs.end();
      if (!applies || !cells.count(k.name)) continue;
      shown.push_back(&k);
      json kj = {{"knob", k.name}, {"levels", json::array()}};
      std::string row = "| " + k.name + " | ";
      std::vector<std::pair<double, double>> stats;
      for (const auto& level : k.levels) {
        const Cell& c = cells[k.name][level];
        const auto [mean, sd] = mean_std(c.values);
        stats.push_back({mean, sd});
        crashes += c.crashes;
        errors += c.errors;
        kj["levels"].push_back({{"level", level},
                                {"runs", c.runs},
                                {"mean", c.values.empty() ? json() : json(mean)},
                                {"std", c.values.empty() ? json() : json(sd)},
                                {"values", c.values},
                                {"crashes", c.crashes},
                                {"errors", c.errors},
                                {"messages", c.messages}});
        row += level + ": " + (c.values.empty() ? "-" : fixed(mean) + " ± " + fixed(sd)) +
               (c.crashes + c.errors
                    ? " (" + std::to_string(c.crashes) + "/" + std::to_string(c.errors) + ")"
                    : "") +
               "; ";
      }
      for (size_t i = 0; i + 1 < stats.size(); ++i) {
        const auto [a, sa] = stats[i];
        const auto [b, sb] = stats[i + 1];
        if (std::isnan(a) || std::isnan(b)) continue;
        const double change = std::abs(a - b), spread = std::max(sa, sb);
        if (change <= spread) continue;
        const bool worse_later = b < a;
        mj["cliffs"].push_back({{"knob", k.name},
                                {"from", worse_later ? k.levels[i] : k.levels[i + 1]},
                                {"to", worse_later ? k.levels[i + 1] : k.levels[i]},
                                {"drop", change},
                                {"seed_spread", spread}});
      }
      mj["knobs"].push_back(kj);
      md += row.substr(0, row.size() - 2) + " |\n";
    }
    mj["crashes"] = crashes;
    mj["errors"] = errors;
    total_crashes += crashes;
    total_errors += errors;
    md += "\nCrashes " + std::to_string(crashes) + ", runs ended with an error " +
          std::to_string(errors) + ".";
    if (!mj["cliffs"].empty()) {
      md += " Cliffs (a drop larger than the seed spread between neighbouring levels):";
      for (const auto& c : mj["cliffs"])
        md += " " + c["knob"].get<std::string>() + " " + c["from"].get<std::string>() + " → " +
              c["to"].get<std::string>() + " (−" + fixed(c["drop"].get<double>()) + ", spread " +
              fixed(c["seed_spread"].get<double>()) + ");";
      md.pop_back();
      md += ".";
    }
    md += "\n";
    doc["methods"].push_back(mj);

    // Heat map: a row per knob, a column per level.
    const double cw = 150, ch = 34, left = 190, top = 50;
    size_t columns = 0;
    for (const Knob* k : shown) columns = std::max(columns, k->levels.size());
    Svg svg(left + cw * double(columns) + 20, top + ch * double(shown.size()) + 40, 12, true);
    svg.text(10, 22,
             name + ": " + headline + " under one failure knob at a time (mean ± std, " + "seeds)",
             "font-weight='bold'");
    for (size_t r = 0; r < shown.size(); ++r) {
      const Knob& k = *shown[r];
      const double y = top + ch * double(r);
      svg.text(10, y + ch / 2 + 4, k.name);
      for (size_t c = 0; c < k.levels.size(); ++c) {
        const Cell& cell = cells[k.name][k.levels[c]];
        const double x = left + cw * double(c);
        const auto [mean, sd] = mean_std(cell.values);
        svg.rect(x + 1, y + 1, cw - 2, ch - 2, cell.values.empty() ? "#cccccc" : colour(mean));
        const std::string label =
            k.levels[c] + ": " + (cell.values.empty() ? "-" : fixed(mean) + " ± " + fixed(sd)) +
            (cell.crashes + cell.errors ? " !" + std::to_string(cell.crashes + cell.errors) : "");
        svg.text(x + 8, y + ch / 2 + 4, label);
      }
    }
    svg.text(10, top + ch * double(shown.size()) + 25,
             "colour: metric 0 (red) to 100 (green); ! = runs that crashed or ended with an error");
    write_file_atomically(results / ("stability_" + name + ".svg"), svg.str());
  }
  doc["crashes"] = total_crashes;
  doc["errors"] = total_errors;
  write_file_atomically(results / "stability.json", doc.dump(2) + "\n");
  write_file_atomically(results / "stability.md", md);
  std::cout << md;
  return 0;
}
