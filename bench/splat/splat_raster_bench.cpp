// bench_splat_raster [--runs R] [--out DIR]: times the CPU rasterizer on random scenes in front of
// a 640x480 camera and writes DIR/splat_raster.json and .svg (default bench/results), printing a
// table. Medians over R runs (default 5) after one warm-up run. Next to the times: the estimated
// floating-point work per view (see FlopEstimate) and the rate it implies.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <tbb/global_control.h>
#include <nlohmann/json.hpp>

#include "base/atomic_file.hpp"
#include "base/random.hpp"
#include "base/svg.hpp"
#include "nodes/splat/raster_state.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "nodes/splat/render_cache.hpp"
#include "runtime/allocator.hpp"

using namespace gslift;

namespace {

constexpr int kWidth = 640, kHeight = 480, kFeatures = 16;

// A scene as a 3DGS reconstruction of a room looks from one view: Gaussians 2-6 m away, filling
// the frustum, scales 0.5-3 cm (log-uniform), opacities spread over (0.1, 0.9), SH degree 3 and
// 16 feature channels.
GaussianModel random_scene(int n, uint32_t seed) {
  RandomStream rng(stream_seed(seed, "bench.raster"));
  auto uniform = [&](float a, float b) { return static_cast<float>(rng.uniform(a, b)); };
  GaussianModel m;
  m.sh_degree = 3;
  m.feature_dim = kFeatures;
  m.resize(n);
  const int K = GaussianModel::sh_coeffs(3);
  for (int i = 0; i < n; ++i) {
    const float z = uniform(2.f, 6.f);
    m.means[3 * i] = uniform(-0.65f, 0.65f) * z;
    m.means[3 * i + 1] = uniform(-0.5f, 0.5f) * z;
    m.means[3 * i + 2] = z;
    for (int k = 0; k < 3; ++k)
      m.log_scales[3 * i + k] = uniform(std::log(0.005f), std::log(0.03f));
    for (int k = 0; k < 4; ++k) m.quats[4 * i + k] = uniform(-1.f, 1.f);
    m.opacity_logits[i] = uniform(-2.2f, 2.2f);
    for (int k = 0; k < K * 3; ++k)
      m.sh[i * K * 3 + k] = k < 3 ? uniform(-1.f, 1.f) : uniform(-0.1f, 0.1f);
    for (int f = 0; f < kFeatures; ++f) m.features[i * kFeatures + f] = uniform(-1.f, 1.f);
  }
  return m;
}

// Floating-point work of one view, counted from the forward pass's tile lists: the blending loops
// evaluate every entry on every pixel of each tile row its rectangle touches (kLanes lanes per
// entry row, used or masked), so that is the count of vector lanes of work. Operations per lane,
// an FMA counted as 2 (read off the loops in raster_state.hpp and rasterizer_*.cpp):
// - blend_row (power, the exp polynomial, alpha, the skip tests): 40
// - forward: transmittance and weight 5, plus 2 per channel
// - backward: blend_row again 40, transmittance and weight 5, dL/dalpha and the running dot
//   product 5, the power moments and opacity 13, plus 4 per channel
// Per Gaussian (projection, SH degree 3 colour, and their backward passes) about 1500 in all,
// small next to the lanes (50k Gaussians: 0.08 GFLOP).
struct FlopEstimate {
  double lanes = 0;           // entry-row lanes evaluated per pass
  double forward_gflop = 0;   // per view
  double backward_gflop = 0;  // per view, the backward pass alone
};

FlopEstimate estimate_flops(const RenderOutput& out, size_t gaussians) {
  const RasterState& s = *out.state;
  FlopEstimate f;
  for (int t = 0; t < s.tile_count(); ++t) {
    const PixelRect tile = tile_pixels(s, t);
    for (uint32_t k = s.tile_offsets[t]; k < s.tile_offsets[t + 1]; ++k) {
      const PixelRect r = clip(s.tile_gaussians[k], tile);
      f.lanes += double(kLanes) * std::max(0, r.y1 - r.y0);
    }
  }
  const double per_gaussian = 1500.0 * gaussians / 2;  // half forward, half backward
  f.forward_gflop = (f.lanes * (40 + 5 + 2 * s.channels) + per_gaussian) * 1e-9;
  f.backward_gflop = (f.lanes * (40 + 5 + 5 + 13 + 4 * s.channels) + per_gaussian) * 1e-9;
  return f;
}

double thread_cpu_ms() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

// Median wall time and median CPU time of the calling thread, in ms. With one TBB thread all work
// runs on the calling thread, so its CPU time is the cost of the work itself, free of the waiting
// that other processes on a shared machine add to the wall time.
struct Timing {
  double wall_ms = 0, cpu_ms = 0;
};

template <class F>
Timing median_ms(int runs, F&& f) {
  f();  // warm-up
  std::vector<double> wall, cpu;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = thread_cpu_ms();
    f();
    cpu.push_back(thread_cpu_ms() - c0);
    wall.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(wall.begin(), wall.end());
  std::sort(cpu.begin(), cpu.end());
  return {wall[wall.size() / 2], cpu[cpu.size() / 2]};
}

struct Row {
  int gaussians = 0, threads = 0;
  double forward_ms = 0, forward_backward_ms = 0;
  double forward_cpu_ms = 0, forward_backward_cpu_ms = 0, cache_render_cpu_ms = 0;
  double cache_build_ms = 0, cache_render_ms = 0, cache_backward_ms = 0;
  double cache_mb = 0, contributions_per_pixel = 0;
  double lanes_per_pixel = 0, forward_gflop = 0, forward_backward_gflop = 0;
};

std::string svg_chart(const std::vector<Row>& rows) {
  // Grouped bars per Gaussian count: forward and forward+backward at 1 and 2 threads, with the
  // 60 ms target as a dashed line.
  const int W = 860, H = 400, left = 60, bottom = 340, top = 40;
  double max_ms = 60;
  for (const Row& r : rows) max_ms = std::max(max_ms, r.forward_backward_ms);
  max_ms *= 1.1;
  auto y = [&](double ms) { return bottom - (bottom - top) * ms / max_ms; };
  const char* colours[4] = {"#9ecae1", "#3182bd", "#fdae6b", "#e6550d"};
  Svg svg(W, H, 12, true);
  svg.text(W / 2, 20,
           "CPU rasterizer, " + std::to_string(kWidth) + "x" + std::to_string(kHeight) +
               ", RGB+depth+normal, ms per view (median wall time; black: CPU time of the work, "
               "1 thread)",
           "text-anchor='middle' font-size='14'");
  for (int t = 0; t <= 5; ++t) {
    const double ms = max_ms * t / 5;
    svg.line(left, y(ms), W - 20, y(ms), "#ddd");
    svg.text(left - 6, y(ms) + 4, std::to_string(int(ms)), "text-anchor='end'");
  }
  std::vector<int> counts;
  for (const Row& r : rows)
    if (std::find(counts.begin(), counts.end(), r.gaussians) == counts.end())
      counts.push_back(r.gaussians);
  const double group = double(W - 20 - left) / counts.size(), bar = group / 6;
  for (size_t g = 0; g < counts.size(); ++g) {
    int b = 0;
    for (const Row& r : rows) {
      if (r.gaussians != counts[g]) continue;
      for (int pass = 0; pass < 2; ++pass) {
        const double ms = pass == 0 ? r.forward_ms : r.forward_backward_ms;
        const int series = 2 * pass + (r.threads == 2 ? 1 : 0);
        const double x = left + g * group + bar + b++ * bar;
        svg.rect(x, y(ms), bar * 0.9, bottom - y(ms), colours[series]);
        if (r.threads == 1) {
          // The CPU time of the work: the wall time without the waiting a shared machine adds.
          const double cpu = pass == 0 ? r.forward_cpu_ms : r.forward_backward_cpu_ms;
          svg.line(x, y(cpu), x + bar * 0.9, y(cpu), "black", "stroke-width='3'");
        }
      }
    }
    svg.text(left + g * group + group / 2, bottom + 18,
             std::to_string(counts[g] / 1000) + "k Gaussians", "text-anchor='middle'");
  }
  svg.line(left, y(60), W - 20, y(60), "red", "stroke-dasharray='6 4'");
  svg.text(W - 22, y(60) - 4, "target fwd+bwd 60 ms", "text-anchor='end' fill='red'");
  const char* names[4] = {"forward, 1 thread", "forward, 2 threads", "fwd+bwd, 1 thread",
                          "fwd+bwd, 2 threads"};
  for (int i = 0; i < 4; ++i) {
    svg.rect(left + i * 160, H - 30, 12, 12, colours[i]);
    svg.text(left + i * 160 + 16, H - 20, names[i]);
  }
  return svg.str();
}

}  // namespace

int main(int argc, char** argv) {
  gslift::keep_freed_memory_in_process();
  int runs = 5;
  std::string out_dir = std::string(GSLIFT_SOURCE_DIR) + "/bench/results";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string arg = argv[i];
    if (arg == "--runs")
      runs = std::max(1, std::stoi(argv[i + 1]));
    else if (arg == "--out")
      out_dir = argv[i + 1];
  }
  Camera camera;
  camera.width = kWidth;
  camera.height = kHeight;
  camera.fx = camera.fy = 525;
  camera.cx = kWidth / 2.0;
  camera.cy = kHeight / 2.0;
  const Pose pose;
  RenderSettings settings;
  settings.depth = settings.normal = true;

  std::vector<Row> rows;
  std::printf(
      "wall ms (CPU ms of the work in brackets, 1 thread only); estimated GFLOP of fwd+bwd per "
      "view and the rate it implies\n");
  std::printf("%9s %7s %18s %18s %14s %9s %10s %11s %16s %9s\n", "gaussians", "threads", "fwd",
              "fwd+bwd", "GFLOP (GFLOP/s)", "cache MB", "contrib/px", "cache build", "cache 16ch",
              "cache bwd");
  for (int n : {20000, 50000, 100000}) {
    const GaussianModel model = random_scene(n, 1234u + n);
    for (int threads : {1, 2}) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      Row row;
      row.gaussians = n;
      row.threads = threads;
      const Timing forward = median_ms(runs, [&] { render(model, camera, pose, settings); });
      row.forward_ms = forward.wall_ms;
      row.forward_cpu_ms = forward.cpu_ms;
      RenderGrads grads;
      ModelGrads model_grads;
      const Timing forward_backward = median_ms(runs, [&] {
        const RenderOutput out = render(model, camera, pose, settings);
        grads.rgb.assign(out.rgb.size(), 1e-3f);
        grads.depth.assign(out.depth.size(), 1e-3f);
        grads.normal.assign(out.normal.size(), 1e-3f);
        model_grads.reset(model);
        render_backward(model, camera, pose, settings, out, grads, model_grads);
      });
      row.forward_backward_ms = forward_backward.wall_ms;
      row.forward_backward_cpu_ms = forward_backward.cpu_ms;
      const FlopEstimate flops =
          estimate_flops(render(model, camera, pose, settings), model.size());
      row.lanes_per_pixel = flops.lanes / (kWidth * kHeight);
      row.forward_gflop = flops.forward_gflop;
      row.forward_backward_gflop = flops.forward_gflop + flops.backward_gflop;
      RenderSettings weights_only;
      weights_only.rgb = false;
      const RenderOutput out = render(model, camera, pose, weights_only);
      row.cache_build_ms = median_ms(runs, [&] { RenderCache cache(out); }).wall_ms;
      const RenderCache cache(out);
      row.cache_mb = cache.bytes() / 1048576.0;
      row.contributions_per_pixel = double(cache.entries()) / (kWidth * kHeight);
      std::vector<float> features(size_t(kWidth) * kHeight * kFeatures);
      const Timing cache_render =
          median_ms(runs, [&] { cache.render(model.features.data(), kFeatures, features.data()); });
      row.cache_render_ms = cache_render.wall_ms;
      row.cache_render_cpu_ms = cache_render.cpu_ms;
      std::vector<float> feature_grad(model.features.size());
      row.cache_backward_ms = median_ms(runs, [&] {
                                std::fill(feature_grad.begin(), feature_grad.end(), 0.f);
                                cache.backward(features.data(), kFeatures, feature_grad.data());
                              }).wall_ms;
      auto both = [&](double wall, double cpu) {
        char buf[64];
        std::snprintf(buf, sizeof buf, threads == 1 ? "%.1f (%.1f)" : "%.1f", wall, cpu);
        return std::string(buf);
      };
      char work[32];
      std::snprintf(work, sizeof work, "%.2f (%.0f)", row.forward_backward_gflop,
                    row.forward_backward_gflop / (row.forward_backward_ms * 1e-3));
      std::printf("%9d %7d %18s %18s %15s %9.1f %10.2f %11.1f %16s %9.1f\n", n, threads,
                  both(row.forward_ms, row.forward_cpu_ms).c_str(),
                  both(row.forward_backward_ms, row.forward_backward_cpu_ms).c_str(), work,
                  row.cache_mb, row.contributions_per_pixel, row.cache_build_ms,
                  both(row.cache_render_ms, row.cache_render_cpu_ms).c_str(),
                  row.cache_backward_ms);
      rows.push_back(row);
    }
  }

  nlohmann::json j;
  j["benchmark"] = "splat_raster";
  j["image"] = {kWidth, kHeight};
  j["channels_timed"] = "rgb (SH degree 3) + depth + normal";
  j["cache_channels"] = kFeatures;
  j["flop_estimate"] =
      "per view, from the lanes the blending loops evaluate (16 per entry and tile row): "
      "forward 45 + 2 C per lane, backward 63 + 4 C, C = 7 channels, plus ~1500 per Gaussian "
      "(bench/splat/splat_raster_bench.cpp, FlopEstimate)";
  j["runs_per_median"] = runs;
  // The machine and how busy it was: wall times on a shared machine include waiting for a core.
  j["hardware_threads"] = std::thread::hardware_concurrency();
  {
    std::ifstream load("/proc/loadavg");
    std::string one_minute;
    if (load >> one_minute) j["load_average_1min_at_end"] = std::stod(one_minute);
  }
  j["scene"] =
      "random: depth 2-6 m filling the frustum, scales 0.5-3 cm log-uniform, opacity "
      "sigmoid(U(-2.2, 2.2))";
  for (const Row& r : rows)
    j["rows"].push_back({{"gaussians", r.gaussians},
                         {"threads", r.threads},
                         {"forward_ms", r.forward_ms},
                         {"forward_backward_ms", r.forward_backward_ms},
                         {"cache_build_ms", r.cache_build_ms},
                         {"cache_render_16ch_ms", r.cache_render_ms},
                         {"cache_backward_16ch_ms", r.cache_backward_ms},
                         {"cache_mb", r.cache_mb},
                         {"contributions_per_pixel", r.contributions_per_pixel},
                         {"blend_lanes_per_pixel", r.lanes_per_pixel},
                         {"forward_gflop_estimate", r.forward_gflop},
                         {"forward_backward_gflop_estimate", r.forward_backward_gflop}});
  // CPU time of the work only where one thread does all of it (2 threads: the calling thread's
  // time would count half the work).
  for (size_t i = 0; i < rows.size(); ++i)
    if (rows[i].threads == 1) {
      j["rows"][i]["forward_cpu_ms"] = rows[i].forward_cpu_ms;
      j["rows"][i]["forward_backward_cpu_ms"] = rows[i].forward_backward_cpu_ms;
      j["rows"][i]["cache_render_16ch_cpu_ms"] = rows[i].cache_render_cpu_ms;
    }
  write_file_atomically(out_dir + "/splat_raster.json", j.dump(2) + "\n");
  write_file_atomically(out_dir + "/splat_raster.svg", svg_chart(rows));
  std::printf("wrote %s/splat_raster.{json,svg}\n", out_dir.c_str());
  return 0;
}
