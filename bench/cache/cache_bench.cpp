// bench_cache: what the stage cache saves (issue 15). graphs/langor.yaml on the embedded OR: a cold
// run (empty cache) against a rerun with only lift.sigma changed (everything before lift loaded
// from the cache), each repeated --repeats times (default 3) and reported as medians, with their
// ratio measured in the same run. Every run is a gslift child process reading its own run.json.
//   bench_cache [--repeats N] [--out DIR]       (default bench/results: cache.json, cache.svg)
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/atomic_file.hpp"
#include "base/statistics.hpp"
#include "base/svg.hpp"
#include "runtime/child_process.hpp"

using namespace gslift;
namespace fs = std::filesystem;

namespace {

struct Timed {
  double total_s = 0;
  int hits = 0;
  double miou = 0;
};

Timed run_langor(const fs::path& cache, const fs::path& out, const std::string& sigma) {
  fs::remove_all(out);
  const ChildRun child = run_child_process(
      {GSLIFT_BINARY, "run", std::string(GSLIFT_SOURCE_DIR) + "/graphs/langor.yaml", "--out",
       out.string(), "--cache-dir", cache.string(), "--set", "lift.sigma=" + sigma, "--threads",
       "2", "--log-level", "warn"},
      (out.string() + ".log"));
  std::ifstream in(out / "run.json");
  if (!child.started || !in)
    throw std::runtime_error("gslift run failed, see " + out.string() + ".log");
  const auto run = nlohmann::json::parse(in);
  if (run["run"]["status"] != "ok") throw std::runtime_error("run failed: " + run["run"].dump());
  Timed t;
  t.total_s = run["run"]["total_s"].get<double>();
  for (const auto& n : run["nodes"]) {
    t.hits += n["cache"] == "hit";
    if (n["id"] == "eval") t.miou = n["records"]["mIoU"].get<double>();
  }
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  int repeats = 3;
  fs::path out_dir = fs::path(GSLIFT_SOURCE_DIR) / "bench/results";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--repeats") repeats = std::max(1, std::stoi(argv[i + 1]));
    if (a == "--out") out_dir = argv[i + 1];
  }
  const fs::path scratch = fs::temp_directory_path() / "gslift_bench_cache";
  fs::create_directories(scratch);
  std::vector<double> cold, warm;
  int warm_hits = 0;
  double cold_miou = 0, warm_miou = 0;
  const char* sigmas[] = {"0.7", "0.6", "0.8"};
  for (int r = 0; r < repeats; ++r) {
    const fs::path cache = scratch / ("cache" + std::to_string(r));
    fs::remove_all(cache);
    const Timed c = run_langor(cache, scratch / "cold", "0.5");
    const Timed w = run_langor(cache, scratch / "warm", sigmas[r % 3]);
    std::cerr << "repeat " << r << ": cold " << c.total_s << " s, sigma " << sigmas[r % 3] << " "
              << w.total_s << " s (" << w.hits << " nodes loaded)\n";
    cold.push_back(c.total_s);
    warm.push_back(w.total_s);
    warm_hits = w.hits;
    cold_miou = c.miou;
    warm_miou = w.miou;
    fs::remove_all(cache);
  }
  const double ratio = median(warm) / median(cold);
  nlohmann::json doc = {{"benchmark", "cache"},
                        {"graph", "graphs/langor.yaml"},
                        {"change", "lift.sigma 0.5 -> 0.7/0.6/0.8 after a cold run"},
                        {"repeats", repeats},
                        {"cold_s", cold},
                        {"rerun_s", warm},
                        {"cold_median_s", median(cold)},
                        {"rerun_median_s", median(warm)},
                        {"ratio", ratio},
                        {"nodes_loaded", warm_hits},
                        {"cold_mIoU", cold_miou},
                        {"last_rerun_mIoU", warm_miou}};
  write_file_atomically(out_dir / "cache.json", doc.dump(2) + "\n");
  Svg svg(520, 170, 12, true);
  svg.text(10, 20,
           "LangOR: cold run vs rerun with lift.sigma changed (median of " +
               std::to_string(repeats) + ", seconds)",
           "font-weight='bold'");
  const double scale = 380.0 / std::max(median(cold), 1e-9);
  const double rows[2] = {median(cold), median(warm)};
  const char* labels[2] = {"cold", "lift.sigma changed"};
  for (int i = 0; i < 2; ++i) {
    const double y = 45 + 50 * i;
    svg.text(10, y + 20, labels[i]);
    svg.rect(130, y, std::max(1.0, rows[i] * scale), 30, i ? "#3a7" : "#47a");
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.2f s", rows[i]);
    svg.text(135 + rows[i] * scale, y + 20, buf);
  }
  char note[96];
  std::snprintf(note, sizeof note, "rerun / cold = %.3f; %d of 13 nodes loaded from the cache",
                ratio, warm_hits);
  svg.text(10, 160, note);
  write_file_atomically(out_dir / "cache.svg", svg.str());
  std::cout << doc.dump(2) << "\n";
  return ratio < 0.1 ? 0 : 1;
}
