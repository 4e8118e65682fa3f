// bench_saga_library: SAGA's library pieces measured without a pipeline (the method's accuracy and
// time are sweeps: bench/saga/saga.tsv):
//  - prompt latency: a trained feature model (FEATURES_PLY, e.g. the affinity/model.ply of a
//    saga.yaml run), padded to 100k Gaussians by repeating Gaussians, answers 200 click prompts at
//    random pixels of the first training view of the embedded OR: selection (PromptSegmenter: the
//    per-Gaussian scores and threshold) plus the mask in the held-out 640x480 view
//    (SelectionMasker, built once before, as gslift segment does; and the render cache's full
//    sparse product for comparison); median, p90, min and max;
//  - one training step's loss and gradient, correspondence against scale-gated, at SAGA's sizes;
//  - masks.auto against the embedded OR's simulated SAM automatic masks: per ground-truth instance
//    of the training views the best IoU of any mask.
// Writes saga_library.json and saga_library.svg into DIR (default bench/results).
//
//   bench_saga_library FEATURES_PLY [DIR] [--threads N]
#include <algorithm>
#include <chrono>
#include <iostream>
#include <string>
#include <vector>

#include <tbb/global_control.h>
#include <nlohmann/json.hpp>

#include "base/atomic_file.hpp"
#include "base/random.hpp"
#include "base/svg.hpp"
#include "nodes/builtin.hpp"
#include "nodes/eval/mask_coverage.hpp"
#include "nodes/features/correspondence_loss.hpp"
#include "nodes/features/scale_gated_loss.hpp"
#include "nodes/inference/prompt_segmentation.hpp"
#include "nodes/inference/selection_mask.hpp"
#include "nodes/inference/text_query.hpp"
#include "nodes/ingest/capture_annotations.hpp"
#include "nodes/ingest/capture_loader.hpp"
#include "nodes/ingest/capture_provider.hpp"
#include "nodes/masks/auto_masks.hpp"
#include "nodes/splat/ply_io.hpp"
#include "runtime/allocator.hpp"

using namespace gslift;
namespace fs = std::filesystem;

namespace {

// Selection + one mask per prompt: the mask from the tile-grouped pairs (SelectionMasker, what
// gslift segment uses) or, for comparison, from the render cache's full sparse product
// (QueryView::mask). Each view structure is built once before the prompts, as gslift segment
// does. Also counts the pixels where the two masks disagree (outside the timing).
nlohmann::json prompt_latency(const fs::path& feature_ply, int threads, bool tile_grouped) {
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  GaussianModel model = read_ply(feature_ply);
  const size_t original = model.size();
  // Pad to 100k Gaussians (the target size) by repeating the first ones: the selection
  // scans every Gaussian, the mask the view's pairs.
  std::vector<size_t> rows;
  for (size_t g = 0; g < 100000; ++g) rows.push_back(g % original);
  model = model.subset(rows);
  const Capture capture = load_capture(resolve_capture_path("embedded:or"), {});
  const int prompt_view = capture.train_views().at(0);
  const View& target = capture.views.at(capture.test_views().at(0));
  PromptSegmenter segmenter(model, capture, {});
  segmenter.feature_map(prompt_view);
  const QueryView qv(model, target.camera, target.pose);
  auto t_build = std::chrono::steady_clock::now();
  const SelectionMasker masker(model, target.camera, target.pose);
  const double build_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_build).count();
  RandomStream rng(stream_seed(0, "bench.saga.clicks"));
  const Camera& cam = capture.views[prompt_view].camera;
  std::vector<double> ms, select_ms;
  std::vector<int64_t> selected;
  size_t pixels = 0, differing = 0;
  for (int k = -20; k < 200; ++k) {  // 20 untimed warm-up prompts
    Prompt p;
    p.view = capture.views[prompt_view].name;
    p.positive = {
        {static_cast<int>(rng.below(cam.width)), static_cast<int>(rng.below(cam.height))}};
    const auto t0 = std::chrono::steady_clock::now();
    const PromptSelection s = segmenter.select(p);
    const double t_select =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const std::vector<float> indicator(s.selected.begin(), s.selected.end());
    const cv::Mat1b mask = tile_grouped ? masker.mask(s.selected, 0.5f) : qv.mask(indicator, 0.5f);
    const double t =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    pixels += static_cast<size_t>(cv::countNonZero(mask));
    if (tile_grouped)
      differing += static_cast<size_t>(cv::countNonZero(mask != qv.mask(indicator, 0.5f)));
    if (k >= 0) ms.push_back(t), select_ms.push_back(t_select), selected.push_back(s.count);
  }
  std::sort(ms.begin(), ms.end());
  std::sort(select_ms.begin(), select_ms.end());
  std::sort(selected.begin(), selected.end());
  nlohmann::json r = {{"gaussians", model.size()},
                      {"gaussians_trained", original},
                      {"threads", threads},
                      {"mask_width", target.camera.width},
                      {"mask_height", target.camera.height},
                      {"prompts_timed", ms.size()},
                      {"median_ms", ms[ms.size() / 2]},
                      {"p90_ms", ms[ms.size() * 9 / 10]},
                      {"min_ms", ms.front()},
                      {"max_ms", ms.back()},
                      {"select_median_ms", select_ms[select_ms.size() / 2]},
                      {"selected_median", selected[selected.size() / 2]},
                      {"selected_max", selected.back()},
                      {"mask_pixels", pixels}};
  if (tile_grouped) {
    r["pixels_differing_from_full_render"] = differing;
    r["build_ms"] = build_ms;
    r["masker_mb"] = masker.bytes() / 1048576.0;
  }
  return r;
}

// One training step's loss and gradient at SAGA's sizes (1000 pixels, 32 channels; scale-gated:
// 10 scales), on random features and masks: what separates the two variants' training time
// (the rendering and the scatter through the blend weights are the same for both). Median of 5.
nlohmann::json loss_step_ms() {
  const int n = 1000, d = 32, scales = 10;
  RandomStream rng(stream_seed(0, "bench.saga.loss"));
  Eigen::MatrixXf f(n, d);
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < d; ++c) f(i, c) = static_cast<float>(rng.normal(0, 1));
  std::vector<int> part(n);
  for (int& p : part) p = static_cast<int>(rng.below(20));
  Eigen::MatrixXf kernel(n, n);
  std::vector<Eigen::MatrixXf> gt(scales, Eigen::MatrixXf(n, n));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      kernel(i, j) = part[i] == part[j] ? 1.f : -1.f;
      for (int k = 0; k < scales; ++k) gt[k](i, j) = part[i] / (k + 1) == part[j] / (k + 1);
    }
  std::vector<float> area(n), gate(2 * d), s(scales);
  for (float& a : area) a = static_cast<float>(rng.uniform(100, 10000));
  for (float& g : gate) g = static_cast<float>(rng.uniform(-1, 1));
  for (int k = 0; k < scales; ++k) s[k] = k / float(scales - 1);
  auto median_ms = [](auto&& run) {
    std::vector<double> t;
    for (int r = 0; r < 5; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      run();
      t.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(t.begin(), t.end());
    return t[t.size() / 2];
  };
  Eigen::MatrixXf grad;
  return {{"pixels", n},
          {"dim", d},
          {"correspondence_ms", median_ms([&] { correspondence_loss(f, kernel, &grad); })},
          {"scale_gated_ms", median_ms([&] {
             scale_gated_loss(f, gt, s, scale_gated_pair_weights(area), gate, 1.0, 1);
           })},
          {"scale_gated_scales", scales}};
}

// How well a set of automatic masks covers the ground-truth instances of the training views
// (eval.mask_coverage's mean best IoU, every granularity together) and the masks per view.
nlohmann::json coverage_json(const Capture& capture, const MaskSet& masks) {
  const MaskCoverage all =
      mask_coverage(masks, ground_truth_masks(capture, ViewSet::Train)).front();
  return {{"instances", all.instances},
          {"mean_best_iou", all.mean_best_iou},
          {"masks_per_view", all.masks_per_view}};
}

// masks.auto (defaults) against the capture's simulated SAM automatic masks on the embedded OR.
nlohmann::json auto_vs_sam() {
  const Capture capture = load_capture(resolve_capture_path("embedded:or"), {});
  return {{"sam_simulated", coverage_json(capture, load_sam_auto_masks(capture))},
          {"masks_auto", coverage_json(capture, auto_mask_set(capture, {}))}};
}

// Median, p90 and max of a prompt, per mask path.
std::string svg_chart(const nlohmann::json& latency) {
  const int left = 60, top = 40, height = 200, group = 150, bar = 36;
  const char* stats[] = {"median_ms", "p90_ms", "max_ms"};
  const char* colours[] = {"#4477aa", "#66ccee", "#ee6677"};
  double top_ms = 1;
  for (const char* path : {"tile_grouped", "sparse_product"})
    top_ms = std::max(top_ms, latency[path]["max_ms"].get<double>());
  Svg svg(left + 2 * group + 40, top + height + 60, 11, true);
  svg.text(left, 20,
           "SAGA prompt: selection + one 640x480 mask, " +
               std::to_string(latency["tile_grouped"]["gaussians"].get<int64_t>()) +
               " Gaussians (ms, lower is better)");
  auto y = [&](double ms) { return top + height - height * ms / top_ms; };
  svg.line(left, y(0), left + 2 * group + 20, y(0), "black");
  int g = 0;
  for (const char* path : {"tile_grouped", "sparse_product"}) {
    const double x0 = left + 10 + group * g++;
    for (int s = 0; s < 3; ++s) {
      const double ms = latency[path][stats[s]].get<double>();
      svg.rect(x0 + bar * s, y(ms), bar - 4, y(0) - y(ms), colours[s]);
      svg.text(x0 + bar * s + bar / 2 - 2, y(ms) - 3, Svg::number(ms), "text-anchor='middle'");
    }
    svg.text(x0 + bar * 1.5, y(0) + 16, path, "text-anchor='middle'");
  }
  for (int s = 0; s < 3; ++s) {
    svg.rect(left + 90 * s, top + height + 34, 10, 10, colours[s]);
    svg.text(left + 90 * s + 14, top + height + 43, stats[s]);
  }
  return svg.str();
}

}  // namespace

int main(int argc, char** argv) {
  keep_freed_memory_in_process();
  int threads = 2, positional = 0;
  fs::path features, out = fs::path(GSLIFT_SOURCE_DIR) / "bench/results";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--threads" && i + 1 < argc)
      threads = std::stoi(argv[++i]);
    else if (!a.empty() && a[0] != '-' && positional < 2)
      (positional++ == 0 ? features : out) = a;
    else
      features.clear(), positional = 3;
  }
  if (features.empty() || positional > 2) {
    std::cerr << "usage: bench_saga_library FEATURES_PLY [DIR] [--threads N]\n";
    return 2;
  }
  Registry registry;
  register_builtin_nodes(registry);  // registers the embedded: capture provider
  const nlohmann::json latency = {{"tile_grouped", prompt_latency(features, threads, true)},
                                  {"sparse_product", prompt_latency(features, threads, false)}};
  std::cerr << "[saga_library] latency " << latency.dump() << "\n";
  const nlohmann::json loss_step = loss_step_ms();
  std::cerr << "[saga_library] loss step " << loss_step.dump() << "\n";
  const nlohmann::json masks = auto_vs_sam();
  std::cerr << "[saga_library] masks " << masks.dump() << "\n";
  const nlohmann::json doc = {
      {"benchmark", "saga_library"}, {"features", features.string()},
      {"threads", threads},          {"prompt_latency", latency},
      {"loss_step_ms", loss_step},   {"automatic_masks_vs_ground_truth", masks}};
  fs::create_directories(out);
  write_file_atomically(out / "saga_library.json", doc.dump(2) + "\n");
  write_file_atomically(out / "saga_library.svg", svg_chart(latency));
  return 0;
}
