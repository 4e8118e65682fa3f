// bench_splat_recon: reconstruction time, Gaussian count and PSNR on training and held-out views,
// with the estimated floating-point work per step next to the measured time.
//
//   bench_splat_recon [--or DIR] [--dtu DIR|none] [--lego FILE|none] [--iterations N] [--out DIR]
//                     [--threads N]
//                     [--ablation 0|1] [--repeat N] [--set KEY=VALUE]...
//   bench_splat_recon --merge NAME OUT_DIR REPORT[:CPU_SECONDS[:LABEL]]...
//
// --set overrides one reconstruction option for every case (keys: splat.reconstruct's params and
// the tuning fields of reconstruct_tuning_table, reconstruct.hpp), e.g. a
// sweep point; --threads caps TBB's parallelism (1 for CPU-time comparisons on a shared machine);
// --repeat runs every case N times and reports the median wall time beside all N.
//
// --or: an embedded OR capture folder (`gslift synth --out DIR`, default settings: 5 views, one
// held out). --dtu: DTU scan 24 (default ../shared/data/dtu_scan24/sparse/0, its COLMAP model
// with SfM points, beside the checkout), loaded
// downscaled 4x with every 8th image held out; its background is NOT masked (the photos are
// trained as they are). --lego: the NeRF-synthetic lego subset (default
// ../shared/data/nerf_synthetic_lego_subset/transforms_subset.json) at 200x200 with every 8th
// view held out, initialised from random points (it has neither points nor depth), 1000 steps
// over white. Writes splat_recon.json and splat_recon.svg into --out (default
// bench/results).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <tbb/global_control.h>
#include <nlohmann/json.hpp>

#include "base/atomic_file.hpp"
#include "base/svg.hpp"
#include "nodes/ingest/capture_loader.hpp"
#include "nodes/splat/reconstruct.hpp"
#include "recon_flops.hpp"
#include "runtime/allocator.hpp"

using namespace gslift;
namespace fs = std::filesystem;

namespace {

struct Case {
  std::string name;  // "or_default", "or_photometric_only", "dtu_scan24"
  fs::path path;
  CaptureOptions load;
  ReconstructOptions options;
};

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

// Runs a case `repeat` times and reports the run with the median wall time (the model and its
// PSNR are the same every time: reconstruction is deterministic) and every run's time.
nlohmann::json run_case(const Case& c, int repeat) {
  std::cerr << "[splat_recon] " << c.name << ": loading " << c.path << "\n";
  const Capture capture = load_capture(c.path, c.load);
  const View& first = capture.views.at(capture.train_views().at(0));
  std::vector<ReconstructResult> runs;
  for (int k = 0; k < repeat; ++k) {
    const auto start = std::chrono::steady_clock::now();
    runs.push_back(reconstruct(capture, c.options, [&](const TrainingStep& s, size_t gaussians) {
      const int step = s.step - 1, total = s.total;
      const double loss = s.loss;
      if ((step + 1) % 25 != 0) return;
      const double t =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::cerr << "[splat_recon] " << c.name << " run " << k + 1 << " step " << step + 1 << "/"
                << total << " loss " << loss << " gaussians " << gaussians << " at " << t << " s\n";
    }));
  }
  std::vector<double> seconds;
  for (const ReconstructResult& run : runs) seconds.push_back(run.seconds);
  std::vector<size_t> order(runs.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return runs[a].seconds < runs[b].seconds; });
  const ReconstructResult& r = runs[order[order.size() / 2]];
  const bench::StepFlops flops = bench::estimate_step_flops(r.model, first);
  const double per_step = r.seconds / std::max(r.iterations_run, 1);
  nlohmann::json j;
  j["case"] = c.name;
  j["capture"] = c.path.string();
  j["views_train"] = capture.train_views().size();
  j["views_test"] = capture.test_views().size();
  j["resolution"] = {first.camera.width, first.camera.height};
  j["iterations"] = r.iterations_run;
  j["depth_weight"] = c.options.depth_weight;
  j["normal_weight"] = c.options.normal_weight;
  j["scale_weight"] = c.options.scale_weight;
  j["seconds"] = r.seconds;  // the median run's
  j["seconds_runs"] = seconds;
  j["seconds_per_step"] = per_step;
  j["phase_seconds"] = {{"prepare", r.phases.prepare}, {"render", r.phases.render},
                        {"losses", r.phases.losses},   {"backward", r.phases.backward},
                        {"adam", r.phases.adam},       {"density", r.phases.density}};
  for (const auto& [term, seconds] : r.phases.terms) j["term_seconds"][term] = seconds;
  j["gaussians_initial"] = r.initial_gaussians;
  j["gaussians_final"] = r.model.size();
  j["train_psnr"] = r.train_psnr;
  j["test_psnr"] = std::isnan(r.test_psnr) ? nlohmann::json() : nlohmann::json(r.test_psnr);
  if (r.test_geometry) {  // held-out geometry against ground-truth depth (view_geometry.hpp)
    const ViewGeometry& g = *r.test_geometry;
    auto number = [](double v) { return std::isnan(v) ? nlohmann::json() : nlohmann::json(v); };
    j["test_geometry"] = {
        {"psnr_covered", number(g.psnr_covered)},
        {"coverage", number(g.coverage)},
        {"depth_abs_rel_median", number(g.depth_abs_rel_median)},
        {"depth_within_5pct", number(g.depth_within_5pct)},
        {"floaters", number(g.floaters)},
        {"floaters_covered", number(g.floaters_covered)},
        {"floaters_expected_depth", number(g.floaters_expected_depth)},
        {"floaters_at_discontinuity", number(g.floaters_at_discontinuity)},
        {"floaters_away_from_discontinuity", number(g.floaters_away_from_discontinuity)},
        {"holes", number(g.holes)},
        {"holes_covered", number(g.holes_covered)}};
  }
  j["final_loss"] = {{"total", r.final_loss.total}};
  for (const auto& [term, value] : r.final_loss.terms) j["final_loss"][term] = value;
  j["estimated_flops_per_step"] = {{"blend_forward", flops.blend_forward},
                                   {"blend_backward", flops.blend_backward},
                                   {"projection", flops.projection},
                                   {"ssim", flops.ssim},
                                   {"adam", flops.adam},
                                   {"total", flops.total()}};
  j["achieved_gflops"] = flops.total() / per_step * 1e-9;
  std::cerr << "[splat_recon] " << j.dump() << "\n";
  return j;
}

// The time a case is charted by: its CPU seconds when recorded (sweeps), else wall seconds.
double charted_seconds(const nlohmann::json& c) {
  return c.contains("cpu_seconds") ? c["cpu_seconds"].get<double>() : c["seconds"].get<double>();
}

// Two horizontal bar panels (seconds, PSNR train/test), one row per case.
std::string svg_chart(const nlohmann::json& cases) {
  const int row = 26, left = 700, width = 300, top = 40;  // left: room for sweep labels
  const int n = static_cast<int>(cases.size());
  const int panel = n * row + 30;
  Svg svg(left + width + 120, top + 2 * panel + 20);
  svg.text(10, 20, "splat reconstruction: time and PSNR", "font-size='14'");
  double max_s = 1, max_p = 1;
  for (const auto& c : cases) {
    max_s = std::max(max_s, charted_seconds(c));
    max_p = std::max(max_p, c["train_psnr"].get<double>());
  }
  for (int i = 0; i < n; ++i) {
    const auto& c = cases[i];
    const int y = top + 20 + i * row;
    const double sec = charted_seconds(c);
    svg.text(10, y + 13, c["case"].get<std::string>());
    svg.rect(left, y, width * sec / max_s, 18, "#4c72b0");
    svg.text(left + width * sec / max_s + 5, y + 13, Svg::number(std::round(sec * 10) / 10) + " s");
    const int yp = top + panel + 20 + i * row;
    const double train = c["train_psnr"].get<double>();
    const double test = c["test_psnr"].is_null() ? 0 : c["test_psnr"].get<double>();
    svg.text(10, yp + 13, c["case"].get<std::string>());
    svg.rect(left, yp, width * train / max_p, 9, "#55a868");
    svg.rect(left, yp + 9, width * test / max_p, 9, "#c44e52");
    svg.text(left + width * train / max_p + 5, yp + 13,
             Svg::number(std::round(train * 10) / 10) + " / " +
                 Svg::number(std::round(test * 10) / 10) + " dB");
  }
  const bool cpu = !cases.empty() && cases[0].contains("cpu_seconds");
  svg.text(10, top + 10, cpu ? "CPU time, 1 thread (s)" : "wall time (s)");
  svg.text(10, top + panel + 10, "PSNR dB: train (green) / held-out (red)");
  return svg.str();
}

// A --set value as the param's type.
ParamValue parse_setting(ParamType type, const std::string& text) {
  switch (type) {
    case ParamType::Int:
      return static_cast<int64_t>(std::stoll(text));
    case ParamType::Float:
      return std::stod(text);
    case ParamType::Bool:
      return text == "true" || text == "1";
    default:
      return text;
  }
}

// Applies "key=value" to the options, the key a param of splat.reconstruct or a tuning field
// (reconstruct_param_table, reconstruct_tuning_table); returns false for an unknown key. Throws
// std::invalid_argument naming the param on a value out of its range.
bool apply_setting(const std::string& setting, ReconstructOptions& o) {
  const size_t eq = setting.find('=');
  if (eq == std::string::npos) return false;
  const std::string key = setting.substr(0, eq), text = setting.substr(eq + 1);
  for (const auto* table : {&reconstruct_param_table(), &reconstruct_tuning_table()})
    for (const auto& f : table->fields())
      if (f.spec.name == key) return table->set(o, key, parse_setting(f.spec.type, text));
  return false;
}

}  // namespace

// --merge: one report (NAME.json + NAME.svg in OUT_DIR) from the cases of earlier runs' reports,
// each case named by its case and its run's --set list; a run's CPU seconds (e.g. from
// /usr/bin/time) and a label (e.g. the code version) may follow its path after colons. Records a
// parameter sweep run as separate processes.
int merge_reports(const std::string& name, const std::vector<std::string>& inputs,
                  const fs::path& out) {
  nlohmann::json merged;
  merged["benchmark"] = "splat_recon (merged runs)";
  merged["cases"] = nlohmann::json::array();
  for (const std::string& input : inputs) {
    // PATH[:CPU_SECONDS[:LABEL]]
    const size_t colon = input.find(':');
    const size_t second = colon == std::string::npos ? colon : input.find(':', colon + 1);
    const std::string path = input.substr(0, colon);
    std::ifstream in(path);
    if (!in) {
      std::cerr << "cannot read " << path << "\n";
      return 2;
    }
    const nlohmann::json report = nlohmann::json::parse(in);
    merged["machine"] = report["machine"];
    const int threads = report["threads"].get<int>();
    std::string settings;
    for (const auto& setting : report["settings"]) settings += " " + setting.get<std::string>();
    for (nlohmann::json c : report["cases"]) {
      const std::string label = c["case"].get<std::string>() + settings;
      c["case"] = label;
      const std::string cpu =
          colon == std::string::npos ? "" : input.substr(colon + 1, second - colon - 1);
      if (!cpu.empty()) c["cpu_seconds"] = std::stod(cpu);
      if (second != std::string::npos) c["case"] = input.substr(second + 1) + ": " + label;
      c["threads"] = threads;  // 0 = all hardware threads
      merged["cases"].push_back(c);
    }
  }
  write_file_atomically(out / (name + ".json"), merged.dump(2) + "\n");
  write_file_atomically(out / (name + ".svg"), svg_chart(merged["cases"]));
  return 0;
}

int main(int argc, char** argv) {
  gslift::keep_freed_memory_in_process();
  if (argc >= 4 && std::string(argv[1]) == "--merge") {
    return merge_reports(argv[2], std::vector<std::string>(argv + 4, argv + argc), argv[3]);
  }
  fs::path or_dir, out = fs::path(GSLIFT_SOURCE_DIR) / "bench" / "results";
  // sparse/0: the COLMAP model with 34k SfM points to initialise from (colmap/ has none).
  fs::path dtu =
      fs::path(GSLIFT_SOURCE_DIR) / ".." / "shared" / "data" / "dtu_scan24" / "sparse" / "0";
  // The NeRF-synthetic lego subset: no points and no depth, so random initialisation (issue 11).
  fs::path lego = fs::path(GSLIFT_SOURCE_DIR) / ".." / "shared" / "data" /
                  "nerf_synthetic_lego_subset" / "transforms_subset.json";
  int iterations = 500;
  int threads = 0;
  int repeat = 1;
  bool ablation = true;
  std::vector<std::string> settings;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--or")
      or_dir = value;
    else if (key == "--dtu")
      dtu = value;
    else if (key == "--lego")
      lego = value;
    else if (key == "--out")
      out = value;
    else if (key == "--iterations")
      iterations = std::stoi(value);
    else if (key == "--threads")
      threads = std::stoi(value);
    else if (key == "--repeat")
      repeat = std::max(1, std::stoi(value));
    else if (key == "--ablation")
      ablation = value != "0";
    else if (key == "--set")
      settings.push_back(value);
    else {
      std::cerr << "unknown option " << key << "\n";
      return 2;
    }
  }
  std::vector<Case> cases;
  ReconstructOptions defaults;
  defaults.iterations = iterations;
  for (const std::string& setting : settings)
    if (!apply_setting(setting, defaults)) {
      std::cerr << "unknown setting " << setting << "\n";
      return 2;
    }
  std::unique_ptr<tbb::global_control> limit;
  if (threads > 0)
    limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                  threads);
  if (!or_dir.empty()) cases.push_back({"or_default", or_dir, {}, defaults});
  if (fs::exists(dtu)) {
    CaptureOptions load;
    load.downscale = 4;
    load.holdout_every = 8;
    load.skip_missing_images = true;
    cases.push_back({"dtu_scan24", dtu, load, defaults});  // no depth prior: sparse points init
  }
  if (fs::exists(lego)) {
    CaptureOptions load;
    load.downscale = 4;      // 200 x 200
    load.holdout_every = 8;  // r_0, r_32, r_64, r_96 held out: 21 training views
    ReconstructOptions o = defaults;
    o.iterations = std::max(iterations, 1000);  // from random points: twice the steps
    o.background = Background::White;           // RGBA renders composited onto white
    cases.push_back({"lego_subset_random_init", lego, load, o});
  }
  if (!or_dir.empty() && ablation) {  // the geometry-loss ablation
    ReconstructOptions photometric = defaults;
    photometric.depth_weight = photometric.normal_weight = photometric.scale_weight = 0;
    cases.push_back({"or_photometric_only", or_dir, {}, photometric});
  }
  nlohmann::json report;
  report["benchmark"] = "splat_recon";
  // The rate the blending loops' vector width allows on this machine, measured with the
  // bench's threads: each case's achieved_gflops is reported as a fraction of it.
  const bench::FmaPeak peak = bench::measure_fma_peak(threads);
  report["machine"] = {{"cpu", cpu_model()},
                       {"hardware_threads", std::thread::hardware_concurrency()},
                       {"fma_peak_gflops", peak.gflops},
                       {"fma_lanes", peak.lanes},
                       {"fma_peak_threads", peak.threads}};
  std::cerr << "[splat_recon] measured single-precision FMA peak " << peak.gflops << " GFLOP/s ("
            << peak.lanes << " lanes, " << peak.threads << " threads)\n";
  report["note"] =
      "DTU background not masked; flops are estimates (recon_flops.hpp), time is wall clock";
  report["settings"] = settings;
  report["threads"] = threads;
  report["cases"] = nlohmann::json::array();
  for (const Case& c : cases) {  // rewritten after every case, so a long run keeps its results
    nlohmann::json result = run_case(c, repeat);
    result["fraction_of_peak"] = result["achieved_gflops"].get<double>() / peak.gflops;
    report["cases"].push_back(std::move(result));
    write_file_atomically(out / "splat_recon.json", report.dump(2) + "\n");
    write_file_atomically(out / "splat_recon.svg", svg_chart(report["cases"]));
  }
  std::cout << report.dump(2) << "\n";
  return 0;
}
