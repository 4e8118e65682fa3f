// HDBSCAN wall time vs point count: n = 1k, 5k, 10k, 20k points of 16-d features (a mixture of
// 12 Gaussian blobs plus 5% uniform noise, like rendered instance features), at 1 and 2 threads,
// median of `reps` runs. Writes DIR/hdbscan.json and DIR/hdbscan.svg (default bench/results).
//
//   bench_hdbscan [DIR] [--reps R] [--sizes 1000,5000,...]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <tbb/global_control.h>
#include <nlohmann/json.hpp>

#include "base/random.hpp"
#include "base/svg.hpp"

#include "base/atomic_file.hpp"
#include "nodes/lifting/hdbscan.hpp"
#include "runtime/allocator.hpp"

using namespace gslift;

namespace {

constexpr int kDim = 16;
constexpr int kBlobs = 12;

PointMatrix blob_features(int n, uint64_t seed) {
  RandomStream rng(stream_seed(seed, "bench.hdbscan"));
  PointMatrix centres(kBlobs, kDim);
  for (int c = 0; c < kBlobs; ++c)
    for (int k = 0; k < kDim; ++k) centres(c, k) = rng.uniform(-4.0, 4.0);
  PointMatrix x(n, kDim);
  for (int i = 0; i < n; ++i) {
    const bool noise = i % 20 == 0;
    for (int k = 0; k < kDim; ++k)
      x(i, k) = noise ? rng.uniform(-4.0, 4.0) : centres(i % kBlobs, k) + 0.3 * rng.normal();
  }
  return x;
}

struct Row {
  int n = 0;
  int threads = 0;
  double median_s = 0;
  std::vector<double> runs_s;
  double median_cpu_s = 0;  // process CPU time (all threads): the work, without waiting
  std::vector<double> cpu_s;
  int clusters = 0;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// The 1-minute load average: the machine is shared, and wall times only mean something next to it.
double load_average() {
  std::ifstream in("/proc/loadavg");
  double load = -1;
  in >> load;
  return load;
}

std::string svg_chart(const std::vector<Row>& rows, const std::vector<int>& sizes) {
  const int W = 640, H = 400, L = 70, R = 20, T = 40, B = 50;
  double max_t = 0;
  for (const auto& r : rows) max_t = std::max(max_t, r.median_s);
  max_t = max_t > 0 ? max_t * 1.1 : 1;
  const double max_n = sizes.empty() ? 1 : *std::max_element(sizes.begin(), sizes.end());
  auto px = [&](double n) { return L + (W - L - R) * n / max_n; };
  auto py = [&](double t) { return H - B - (H - T - B) * t / max_t; };
  Svg svg(W, H, 12, true);
  svg.text(W / 2, 20, "HDBSCAN (exact, " + std::to_string(kDim) + "-d): median wall time vs points",
           "text-anchor='middle' font-size='14'");
  svg.line(L, H - B, W - R, H - B, "black");
  svg.line(L, T, L, H - B, "black");
  for (const int n : sizes) svg.text(px(n), H - B + 18, std::to_string(n), "text-anchor='middle'");
  for (int i = 0; i <= 4; ++i) {
    const double t = max_t * i / 4;
    char label[32];
    std::snprintf(label, sizeof label, "%.2f s", t);
    svg.text(L - 6, py(t) + 4, label, "text-anchor='end'");
  }
  svg.text((L + W - R) / 2, H - 10, "points", "text-anchor='middle'");
  const char* colours[] = {"#1f77b4", "#d62728"};
  for (int threads = 1; threads <= 2; ++threads) {
    std::vector<std::array<double, 2>> points;
    for (const auto& r : rows)
      if (r.threads == threads) points.push_back({px(r.n), py(r.median_s)});
    svg.polyline(points, colours[threads - 1], 2);
    svg.text(L + 10, T + 16 * threads,
             std::to_string(threads) + (threads == 1 ? " thread" : " threads"),
             std::string("fill='") + colours[threads - 1] + "'");
  }
  return svg.str();
}

}  // namespace

int main(int argc, char** argv) {
  gslift::keep_freed_memory_in_process();
  std::string out_dir = std::string(GSLIFT_SOURCE_DIR) + "/bench/results";
  int reps = 3;
  std::vector<int> sizes{1000, 5000, 10000, 20000};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--reps" && i + 1 < argc) {
      reps = std::max(1, std::stoi(argv[++i]));
    } else if (a == "--sizes" && i + 1 < argc) {
      sizes.clear();
      std::istringstream list(argv[++i]);
      std::string item;
      while (std::getline(list, item, ',')) sizes.push_back(std::stoi(item));
    } else {
      out_dir = a;
    }
  }

  HdbscanParams params;
  params.min_cluster_size = 10;
  std::vector<Row> rows;
  const double load_before = load_average();
  for (const int n : sizes) {
    const PointMatrix x = blob_features(n, 1234);
    for (int threads = 1; threads <= 2; ++threads) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      Row row;
      row.n = n;
      row.threads = threads;
      for (int r = 0; r < reps; ++r) {
        const auto start = std::chrono::steady_clock::now();
        const std::clock_t cpu_start = std::clock();
        const HdbscanResult result = hdbscan(x, params);
        row.cpu_s.push_back(static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC);
        row.runs_s.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        row.clusters = result.clusters;
      }
      row.median_s = median(row.runs_s);
      row.median_cpu_s = median(row.cpu_s);
      std::printf("n=%6d threads=%d median %.3f s wall, %.3f s CPU (%d clusters)\n", n, threads,
                  row.median_s, row.median_cpu_s, row.clusters);
      std::fflush(stdout);
      rows.push_back(row);
    }
  }

  nlohmann::json j;
  j["benchmark"] = "hdbscan";
  j["dim"] = kDim;
  j["blobs"] = kBlobs;
  j["min_cluster_size"] = params.min_cluster_size;
  j["repetitions"] = reps;
  j["hardware_threads"] = std::thread::hardware_concurrency();
  j["load_average_before"] = load_before;
  j["load_average_after"] = load_average();
  for (const auto& r : rows)
    j["results"].push_back({{"points", r.n},
                            {"threads", r.threads},
                            {"median_seconds", r.median_s},
                            {"runs_seconds", r.runs_s},
                            {"median_cpu_seconds", r.median_cpu_s},
                            {"cpu_seconds", r.cpu_s},
                            {"clusters", r.clusters}});
  write_file_atomically(out_dir + "/hdbscan.json", j.dump(2) + "\n");
  write_file_atomically(out_dir + "/hdbscan.svg", svg_chart(rows, sizes));
  std::printf("wrote %s/hdbscan.{json,svg}\n", out_dir.c_str());
  return 0;
}
