// bench_saga: accuracy, time, memory and prompt latency of SAGA (paper 001).
//
//   bench_saga [--variants saga,saga_no_filter_3d,...] [--no-dtu] [--out DIR] [--threads N]
//              [--features PLY]   (the latency's feature model, instead of the saga run's)
//
// Accuracy: runs graphs/saga.yaml and its ablations (graphs/ablations/saga_*.yaml) on the
// embedded OR (seed 0), and graphs/saga_dtu.yaml (+ ablations/saga_dtu_point.yaml) on
// ../shared/data/dtu_scan24 when it is there, one child `gslift run` per graph (its peak memory
// from wait4); reads mIoU / mAcc, the feature training's seconds and cache from run.json. DTU:
// the run's selection (render/scene_selection.ply) is also rendered at the 24 poses without
// photos (their cameras from sparse/0, at the graph's 1/4 scale) and scored against mask/.
// Latency: the OR run's feature model (affinity/model.ply), padded to 100k Gaussians by
// repeating Gaussians, answers 200 click prompts at random pixels of the first training view:
// selection (the per-Gaussian scores and threshold) plus the mask in the held-out 640x480 view
// (SelectionMasker, built once before, as gslift segment does; and the full sparse product for
// comparison); median, p90, min and max. Writes saga.json, saga.csv and saga.svg into --out
// (bench/results).
#include <algorithm>
#include <chrono>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <tbb/global_control.h>
#include <nlohmann/json.hpp>

#include "base/atomic_file.hpp"
#include "base/random.hpp"
#include "base/svg.hpp"
#include "nodes/builtin.hpp"
#include "nodes/eval/binary_segmentation.hpp"
#include "nodes/features/correspondence_loss.hpp"
#include "nodes/features/scale_gated_loss.hpp"
#include "nodes/inference/prompt_segmentation.hpp"
#include "nodes/inference/selection_mask.hpp"
#include "nodes/inference/selection_output.hpp"
#include "nodes/inference/text_query.hpp"
#include "nodes/ingest/capture_annotations.hpp"
#include "nodes/ingest/capture_loader.hpp"
#include "nodes/ingest/capture_provider.hpp"
#include "nodes/ingest/colmap_model.hpp"
#include "nodes/masks/auto_masks.hpp"
#include "nodes/splat/ply_io.hpp"
#include "runtime/allocator.hpp"
#include "runtime/child_process.hpp"

using namespace gslift;
namespace fs = std::filesystem;

namespace {

fs::path graph_file(const std::string& v) {
  const fs::path src(GSLIFT_SOURCE_DIR);
  return v == "saga" || v == "saga_dtu" ? src / "graphs" / (v + ".yaml")
                                        : src / "graphs/ablations" / (v + ".yaml");
}

const fs::path kDtu = fs::path(GSLIFT_SOURCE_DIR) / "../shared/data/dtu_scan24";

struct Run {
  bool ok = false;
  nlohmann::json run;  // run.json
  double wall_s = 0, peak_mb = 0;
  fs::path out;
  double record(const std::string& node, const std::string& key) const {
    for (const auto& n : run["nodes"])
      if (n["id"] == node && n["records"].contains(key)) return n["records"][key].get<double>();
    return NAN;
  }
};

Run run_child(const std::string& variant, const fs::path& scratch, int threads) {
  Run r;
  r.out = scratch / variant;
  fs::remove_all(r.out);
  // --no-cache: the bench times the whole pipeline, not a load from the stage cache.
  const ChildRun child = run_child_process({GSLIFT_BINARY, "run", graph_file(variant).string(),
                                            "--out", r.out.string(), "--log-level", "warn",
                                            "--threads", std::to_string(threads), "--no-cache"});
  if (!child.started) return r;
  r.peak_mb = child.peak_mb;
  std::ifstream in(r.out / "run.json");
  if (!in) return r;
  r.run = nlohmann::json::parse(in);
  r.ok = r.run["run"]["status"] == "ok";
  if (r.ok) r.wall_s = r.run["run"]["total_s"].get<double>();
  return r;
}

nlohmann::json accuracy_entry(const std::string& variant, const Run& r) {
  nlohmann::json e = {{"variant", variant}, {"ok", r.ok}};
  if (!r.ok) return e;
  e["mIoU"] = r.record("eval", "mIoU");
  e["mAcc"] = r.record("eval", "mAcc");
  e["target_views"] = r.record("eval", "target_views");
  e["wall_s"] = r.wall_s;
  e["peak_rss_mb"] = r.peak_mb;
  e["features_s"] = r.record("affinity", "seconds");
  e["features_cache_mb"] = r.record("affinity", "cache_bytes") / 1048576.0;
  e["features_loss_end"] = r.record("affinity", "loss_end");
  e["select_ms_median"] = r.record("prompt", "select_ms_median");
  return e;
}

// The DTU selection of a saga_dtu run scored at the 24 poses without photos.
nlohmann::json dtu_pose_only(const Run& r) {
  const GaussianModel model = read_ply(r.out / "render/scene_selection.ply");
  const ColmapModel colmap = read_colmap_model(kDtu / "sparse/0");
  Capture capture;
  std::vector<int> pose_only;
  for (const ColmapImage& im : colmap.images) {
    View v;
    v.name = fs::path(im.name).stem().string();
    v.camera = colmap.cameras.at(im.camera_id).scaled(0.25);  // the graph's downscale 4
    v.camera.distortion.clear();  // kept as a pinhole, as the graph does (undistort: false)
    v.pose = im.pose;
    if (!fs::exists(kDtu / "images" / im.name))
      pose_only.push_back(static_cast<int>(capture.views.size()));
    capture.views.push_back(v);
  }
  const MaskSet truth = mask_folder(capture, kDtu / "mask", ViewSet::All, "scan24");
  const MaskSet pred = render_selection_masks(model, capture, pose_only, {"scan24"});
  const BinarySegmentationSummary s = score_binary_segmentation(pred, truth, {});
  return {{"views", s.views.size()}, {"mIoU", s.miou}, {"mAcc", s.macc}};
}

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

// How well a set of automatic masks covers the ground-truth instances of the training views: per
// instance the best IoU of any mask (any granularity), averaged; and the masks per view.
nlohmann::json mask_coverage(const Capture& capture, const MaskSet& masks) {
  const MaskSet truth = ground_truth_masks(capture, ViewSet::Train);
  double sum = 0;
  int instances = 0, count = 0;
  for (const ViewMasks& tv : truth.views)
    for (const ViewMasks& mv : masks.views) {
      if (mv.view != tv.view) continue;
      count += static_cast<int>(mv.masks.size());
      for (const Mask& t : tv.masks) {
        double best = 0;
        for (const Mask& m : mv.masks) best = std::max(best, mask_iou(m.pixels, t.pixels));
        sum += best;
        ++instances;
      }
    }
  return {{"instances", instances},
          {"mean_best_iou", instances ? 100.0 * sum / instances : NAN},
          {"masks_per_view", truth.views.empty() ? 0.0 : double(count) / truth.views.size()}};
}

// masks.auto (defaults) against the capture's simulated SAM automatic masks on the embedded OR.
nlohmann::json auto_vs_sam() {
  const Capture capture = load_capture(resolve_capture_path("embedded:or"), {});
  return {{"sam_simulated", mask_coverage(capture, load_sam_auto_masks(capture))},
          {"masks_auto", mask_coverage(capture, auto_mask_set(capture, {}))}};
}

std::string svg_chart(const nlohmann::json& entries) {
  const int bar = 18, group = 2 * bar + 30, left = 50, top = 30, height = 200;
  const int width = std::max(460, left + group * static_cast<int>(entries.size()) + 20);
  Svg svg(width, top + height + 90, 11);
  for (int v = 0; v <= 100; v += 25) {
    const double y = top + height - height * v / 100.0;
    svg.line(left, y, width - 10, y, "#ddd");
    svg.text(left - 6, y + 4, std::to_string(v), "text-anchor='end'");
  }
  const char* colours[] = {"#4477aa", "#ee6677"};
  const char* names[] = {"mIoU", "mAcc"};
  int i = 0;
  for (const auto& e : entries) {
    const double x0 = left + 10 + group * i++;
    for (int m = 0; m < 2; ++m) {
      if (!e.contains(names[m])) continue;
      const double h = height * e[names[m]].get<double>() / 100.0;
      svg.rect(x0 + bar * m, top + height - h, bar - 2, h, colours[m]);
    }
    svg.text(x0 + bar, top + height + 14, e["variant"].get<std::string>(),
             "text-anchor='end' transform='rotate(-35 " + std::to_string(x0 + bar) + " " +
                 std::to_string(top + height + 14) + ")'");
  }
  for (int m = 0; m < 2; ++m) {
    svg.rect(left + 80 * m, top + height + 74, 10, 10, colours[m]);
    svg.text(left + 80 * m + 14, top + height + 83, names[m]);
  }
  svg.text(left, 18, "SAGA: binary segmentation, embedded OR and DTU scan 24 (percent)");
  return svg.str();
}

}  // namespace

int main(int argc, char** argv) {
  keep_freed_memory_in_process();
  std::vector<std::string> variants = {"saga", "saga_no_filter_3d", "saga_mask_prompt",
                                       "saga_auto_masks", "saga_scale_gated"};
  bool dtu = true;
  int threads = 2;
  fs::path feature_model;  // the latency's model: --features, else the saga run's
  fs::path out = fs::path(GSLIFT_SOURCE_DIR) / "bench/results";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--variants" && i + 1 < argc) {
      variants.clear();
      std::stringstream list(argv[++i]);
      for (std::string v; std::getline(list, v, ',');) variants.push_back(v);
    } else if (a == "--no-dtu") {
      dtu = false;
    } else if (a == "--out" && i + 1 < argc) {
      out = argv[++i];
    } else if (a == "--features" && i + 1 < argc) {
      feature_model = argv[++i];
    } else if (a == "--threads" && i + 1 < argc) {
      threads = std::stoi(argv[++i]);
    } else {
      std::cerr << "usage: bench_saga [--variants a,b] [--no-dtu] [--out DIR] [--threads N] "
                   "[--features PLY]\n";
      return 2;
    }
  }
  Registry registry;
  register_builtin_nodes(registry);  // registers the embedded: capture provider
  const fs::path scratch = fs::temp_directory_path() / "bench_saga";
  nlohmann::json entries = nlohmann::json::array();
  std::ostringstream csv;
  csv << "variant,mIoU,mAcc,wall_s,peak_rss_mb,features_s,features_cache_mb\n";
  auto add = [&](const std::string& v, const Run& r) {
    nlohmann::json e = accuracy_entry(v, r);
    std::cerr << "[saga] " << e.dump() << "\n";
    if (r.ok)
      csv << v << "," << e["mIoU"] << "," << e["mAcc"] << "," << e["wall_s"] << ","
          << e["peak_rss_mb"] << "," << e["features_s"] << "," << e["features_cache_mb"] << "\n";
    entries.push_back(e);
  };
  for (const std::string& v : variants) {
    const Run r = run_child(v, scratch, threads);
    if (v == "saga" && r.ok && feature_model.empty()) feature_model = r.out / "affinity/model.ply";
    add(v, r);
  }
  nlohmann::json dtu_results = nullptr;
  if (dtu && fs::exists(kDtu / "sparse/0")) {
    dtu_results = nlohmann::json::object();
    for (const std::string v : {"saga_dtu", "saga_dtu_point"}) {
      const Run r = run_child(v, scratch, threads);
      add(v, r);
      if (r.ok) {
        dtu_results[v] = dtu_pose_only(r);
        entries.back()["pose_only"] = dtu_results[v];
        std::cerr << "[saga] " << v << " pose-only views: " << dtu_results[v].dump() << "\n";
      }
    }
  }
  nlohmann::json latency = nullptr;
  if (!feature_model.empty())
    latency = {{"tile_grouped", prompt_latency(feature_model, threads, true)},
               {"sparse_product", prompt_latency(feature_model, threads, false)}};
  std::cerr << "[saga] latency " << (latency.is_null() ? "-" : latency.dump()) << "\n";
  const nlohmann::json loss_step = loss_step_ms();
  std::cerr << "[saga] loss step " << loss_step.dump() << "\n";
  const nlohmann::json masks = auto_vs_sam();
  std::cerr << "[saga] masks " << masks.dump() << "\n";
  const nlohmann::json doc = {{"benchmark", "saga"},
                              {"threads", threads},
                              {"note", "wall clock on a shared 2-core machine; seed 0"},
                              {"variants", entries},
                              {"prompt_latency", latency},
                              {"loss_step_ms", loss_step},
                              {"automatic_masks_vs_ground_truth", masks}};
  fs::create_directories(out);
  write_file_atomically(out / "saga.json", doc.dump(2) + "\n");
  write_file_atomically(out / "saga.csv", csv.str());
  write_file_atomically(out / "saga.svg", svg_chart(entries));
  return 0;
}
