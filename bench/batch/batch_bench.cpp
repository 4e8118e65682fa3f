// Many captures in one batch (issue 16): 20 small embedded-OR captures through
// tests/batch/tiny.yaml on 2 threads, once as separate `gslift run` processes (the sum of the
// parts) and once as one `gslift batch` process. Reports the batch's total time against the sum of
// the parts, and each capture's peak memory inside the batch (run.json peak_rss_mb: the batch
// resets the peak before every capture, runtime/batch.cpp) against the same capture run alone, with
// a least-squares slope across captures: memory is flat when the slope is ~0 MB per capture. JSON +
// SVG under bench/results.
//
// usage: batch_bench [--captures N] [--iterations I] [--threads T] [--results DIR]
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numeric>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/atomic_file.hpp"
#include "base/svg.hpp"
#include "runtime/child_process.hpp"

namespace fs = std::filesystem;
using nlohmann::json;
using namespace gslift;

namespace {

struct Capture {
  std::string name;
  double alone_s = 0, alone_peak_mb = 0;  // `gslift run` of this capture alone (its own process)
  double batch_s = 0, batch_peak_mb = 0;  // inside `gslift batch` (run.json total_s, peak_rss_mb)
};

json read_json(const fs::path& f) {
  std::ifstream in(f);
  return json::parse(in);
}

// Least-squares slope of y over 0..n-1.
double slope(const std::vector<double>& y) {
  const double n = static_cast<double>(y.size());
  const double mx = (n - 1) / 2, my = std::accumulate(y.begin(), y.end(), 0.0) / n;
  double sxy = 0, sxx = 0;
  for (size_t i = 0; i < y.size(); ++i) {
    sxy += (i - mx) * (y[i] - my);
    sxx += (i - mx) * (i - mx);
  }
  return sxx > 0 ? sxy / sxx : 0;
}

// Two panels: seconds per capture (alone vs in the batch), peak MB per capture (alone vs batch).
std::string chart(const std::vector<Capture>& caps, double sum_alone, double batch_wall,
                  double mb_slope) {
  const int w = 720, h = 320, panel = 340, left = 50, top = 70, bottom = 40;
  Svg svg(w, h, 11, true);
  svg.text(10, 16,
           std::to_string(caps.size()) + " small captures, 2 threads: one gslift batch " +
               Svg::number(batch_wall) + " s vs " + std::to_string(caps.size()) +
               " separate gslift runs " + Svg::number(sum_alone) + " s");
  svg.text(10, 32,
           "peak memory per capture inside the batch: slope " + Svg::number(mb_slope) +
               " MB per capture");
  svg.text(10, 50, "grey: gslift run alone", "fill='#777777'");
  svg.text(160, 50, "blue: inside gslift batch", "fill='#2e6da4'");
  auto draw = [&](int x0, const std::string& title, auto alone, auto batch) {
    double top_value = 0;
    for (const auto& c : caps) top_value = std::max({top_value, alone(c), batch(c)});
    top_value *= 1.15;
    const double inner_w = panel - left - 10, inner_h = h - top - bottom;
    auto X = [&](size_t i) { return x0 + left + inner_w * (i + 0.5) / caps.size(); };
    auto Y = [&](double v) { return top + inner_h * (1 - v / top_value); };
    svg.text(x0 + left, top - 8, title);
    svg.line(x0 + left, top + inner_h, x0 + left + inner_w, top + inner_h, "black");
    svg.line(x0 + left, top, x0 + left, top + inner_h, "black");
    for (double v : {0.0, top_value / 2, top_value / 1.15})
      svg.text(x0 + 4, Y(v) + 4, Svg::number(std::round(v * 100) / 100));
    std::vector<std::array<double, 2>> a, b;
    for (size_t i = 0; i < caps.size(); ++i) {
      a.push_back({X(i), Y(alone(caps[i]))});
      b.push_back({X(i), Y(batch(caps[i]))});
    }
    svg.polyline(a, "#999999", 1.5);
    svg.polyline(b, "#2e6da4", 2);
    svg.text(x0 + left, h - 12, "capture 1.." + std::to_string(caps.size()));
  };
  draw(
      0, "seconds per capture", [](const Capture& c) { return c.alone_s; },
      [](const Capture& c) { return c.batch_s; });
  draw(
      panel + 20, "peak RSS (MB) per capture", [](const Capture& c) { return c.alone_peak_mb; },
      [](const Capture& c) { return c.batch_peak_mb; });
  return svg.str();
}

}  // namespace

int main(int argc, char** argv) {
  int captures = 20, iterations = 150, threads = 2;
  fs::path results = fs::path(GSLIFT_SOURCE_DIR) / "bench" / "results";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--captures") captures = std::atoi(argv[i + 1]);
    if (a == "--iterations") iterations = std::atoi(argv[i + 1]);
    if (a == "--threads") threads = std::atoi(argv[i + 1]);
    if (a == "--results") results = argv[i + 1];
  }
  const std::string gslift = GSLIFT_BINARY;
  const std::string graph = fs::path(GSLIFT_SOURCE_DIR) / "tests" / "batch" / "tiny.yaml";
  const fs::path work =
      fs::temp_directory_path() / ("gslift_batch_bench_" + std::to_string(getpid()));
  fs::remove_all(work);
  fs::create_directories(work);
  const std::string set = "iterations=" + std::to_string(iterations);
  const std::string th = std::to_string(threads);

  // The captures: different layouts and phases, 96 x 72, 4 views.
  std::vector<Capture> caps;
  std::ofstream manifest(work / "manifest.txt");
  const char* phases[] = {"preparation", "surgery", "closing"};
  for (int k = 0; k < captures; ++k) {
    Capture c;
    c.name = "or_" + std::to_string(k);
    const auto r =
        run_child_process({gslift, "synth", "--out", (work / "in" / c.name).string(), "--seed",
                           std::to_string(k), "--phase", phases[k % 3], "--views", "4", "--width",
                           "96", "--height", "72", "--log-level", "warn"});
    if (!r.started || r.status != 0) return std::cerr << "synth failed\n", 1;
    manifest << "in/" << c.name << "\n";
    caps.push_back(c);
  }
  manifest.close();

  // The parts: each capture alone, a process each.
  double sum_alone = 0;
  for (auto& c : caps) {
    const auto r =
        run_child_process({gslift, "run", graph, "--input", (work / "in" / c.name).string(),
                           "--out", (work / "alone" / c.name).string(), "--set", set, "--threads",
                           th, "--log-level", "warn", "--no-cache"});
    if (!r.started || r.status != 0) return std::cerr << "run failed for " << c.name << "\n", 1;
    c.alone_s = r.wall_s;
    c.alone_peak_mb = r.peak_mb;
    sum_alone += r.wall_s;
  }
  // The batch: one process.
  const auto b = run_child_process({gslift, "batch", (work / "manifest.txt").string(), graph,
                                    "--out", (work / "batch").string(), "--set", set, "--threads",
                                    th, "--log-level", "warn", "--no-cache"});
  if (!b.started || b.status != 0) return std::cerr << "batch failed\n", 1;
  std::vector<double> peaks;
  json rows = json::array();
  for (auto& c : caps) {
    const json run = read_json(work / "batch" / c.name / "run.json")["run"];
    c.batch_s = run["total_s"];
    c.batch_peak_mb = run["peak_rss_mb"];
    peaks.push_back(c.batch_peak_mb);
    rows.push_back({{"capture", c.name},
                    {"alone_s", c.alone_s},
                    {"alone_peak_mb", c.alone_peak_mb},
                    {"batch_s", c.batch_s},
                    {"batch_peak_mb", c.batch_peak_mb}});
  }
  const double mb_slope = slope(peaks);
  const double sum_in_batch = std::accumulate(
      caps.begin(), caps.end(), 0.0, [](double s, const Capture& c) { return s + c.batch_s; });
  const json out = {
      {"bench", "batch"},
      {"command", "batch_bench --captures " + std::to_string(captures) + " --iterations " +
                      std::to_string(iterations) + " --threads " + th},
      {"graph", "tests/batch/tiny.yaml"},
      {"capture", "embedded OR, 96x72, 4 views, seeds 0..N-1, phases cycled"},
      {"captures", captures},
      {"threads", threads},
      {"iterations", iterations},
      {"sum_of_separate_runs_s", sum_alone},
      {"batch_wall_s", b.wall_s},
      {"batch_over_sum", b.wall_s / sum_alone},
      {"sum_of_captures_in_batch_s", sum_in_batch},
      {"batch_overhead_s", b.wall_s - sum_in_batch},
      {"batch_process_peak_mb", b.peak_mb},
      {"batch_capture_peak_mb_first", peaks.front()},
      {"batch_capture_peak_mb_last", peaks.back()},
      {"batch_capture_peak_mb_max", *std::max_element(peaks.begin(), peaks.end())},
      {"batch_capture_peak_mb_slope_per_capture", mb_slope},
      {"per_capture", rows}};
  fs::create_directories(results);
  write_file_atomically(results / "batch.json", out.dump(2) + "\n");
  write_file_atomically(results / "batch.svg", chart(caps, sum_alone, b.wall_s, mb_slope));
  std::cout << "sum of " << captures << " separate runs " << sum_alone << " s, batch " << b.wall_s
            << " s (x" << b.wall_s / sum_alone << "), captures inside the batch " << sum_in_batch
            << " s; peak MB per capture in the batch: first " << peaks.front() << ", last "
            << peaks.back() << ", slope " << mb_slope << " MB/capture\n";
  fs::remove_all(work);
  return 0;
}
