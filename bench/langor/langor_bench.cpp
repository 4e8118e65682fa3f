// bench_langor: accuracy, stability, speed and memory of LangOR on the embedded operating room.
//
//   bench_langor [--seeds N] [--variants langor,no_geometry,...] [--out DIR] [--set NODE.P=V]...
//                [--capture "&width=320&height=240"] [--no-timing] [--query-graph GRAPH]
//
// A variant is a graph (langor or an ablation's file name) optionally followed by its own sets:
// "langor+recon.prune_behind=0.7+recon.line_of_sight_weight=0.8" is langor.yaml with those two
// params (a reconstruction lever of the held-out geometry sweep, bench/splat_recon/README.md).
//
// Accuracy: runs graphs/langor.yaml and each ablation (graphs/ablations/*.yaml) with the gslift
// executable on embedded:or?seed=S for S = 0..N-1 (default 5; default difficulty), one child
// process per run so that each run's peak memory (wait4 ru_maxrss) is its own; reads mIoU,
// mLocAcc, mAcc from the run's run.json, and the reconstruction's held-out geometry records
// (test_psnr, test_psnr_covered, test_floaters, ...) from its recon node. Query speed: runs the
// full graph once in this process (seed 0) and times text queries (instance selection + one mask of
// the held-out view) on its segmented scene. Writes langor.json, langor.csv and langor.svg into
// --out (default bench/results).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/atomic_file.hpp"
#include "base/statistics.hpp"
#include "base/svg.hpp"
#include "nodes/builtin.hpp"
#include "nodes/inference/text_query.hpp"
#include "runtime/allocator.hpp"
#include "runtime/child_process.hpp"
#include "runtime/executor.hpp"

using namespace gslift;
namespace fs = std::filesystem;

namespace {

const char* kMetrics[] = {"mIoU", "mLocAcc", "mAcc", "mLocAcc_box", "mIoU_class"};
// splat.reconstruct's records (node id "recon"): held-out geometry (view_geometry.hpp).
const char* kReconMetrics[] = {"train_psnr",    "test_psnr",          "test_psnr_covered",
                               "test_coverage", "test_floaters",      "test_floaters_covered",
                               "test_holes",    "test_holes_covered", "test_depth_abs_rel_median",
                               "gaussians"};

// "graph+NODE.P=V+..." -> the graph's name and the variant's own sets.
std::pair<std::string, std::vector<std::string>> split_variant(const std::string& v) {
  std::vector<std::string> parts;
  std::stringstream list(v);
  for (std::string p; std::getline(list, p, '+');) parts.push_back(p);
  if (parts.empty()) return {v, {}};
  return {parts[0], std::vector<std::string>(parts.begin() + 1, parts.end())};
}

fs::path variant_graph(const std::string& variant) {
  const std::string v = split_variant(variant).first;
  const fs::path src(GSLIFT_SOURCE_DIR);
  return v == "langor" ? src / "graphs/langor.yaml" : src / "graphs/ablations" / (v + ".yaml");
}

struct RunStats {
  bool ok = false;
  std::map<std::string, double> metrics;
  double wall_s = 0;
  double peak_mb = 0;
};

// One child `gslift run`; its own peak RSS comes from wait4.
RunStats run_child(const std::string& variant, int seed, const std::string& capture_settings,
                   const std::vector<std::string>& sets, const fs::path& scratch) {
  std::string folder = variant;  // the variant's name with its sets, as a folder name
  std::replace_if(
      folder.begin(), folder.end(), [](char c) { return c == '/' || c == '='; }, '_');
  const fs::path out = scratch / (folder + "_seed" + std::to_string(seed));
  fs::remove_all(out);
  std::vector<std::string> args = {GSLIFT_BINARY,
                                   "run",
                                   variant_graph(variant).string(),
                                   "--input",
                                   "embedded:or?seed=" + std::to_string(seed) + capture_settings,
                                   "--out",
                                   out.string(),
                                   "--log-level",
                                   "warn",
                                   "--no-cache"};  // time the pipeline, not the stage cache
  std::vector<std::string> all_sets = sets;
  for (const auto& s : split_variant(variant).second) all_sets.push_back(s);
  for (const auto& s : all_sets) {
    args.push_back("--set");
    args.push_back(s);
  }
  RunStats r;
  const ChildRun child = run_child_process(args);
  if (!child.started) {
    std::cerr << "[langor] cannot start " << args[0] << "\n";
    return r;
  }
  r.wall_s = child.wall_s;
  r.peak_mb = child.peak_mb;
  std::ifstream in(out / "run.json");
  if (!in) return r;
  const nlohmann::json run = nlohmann::json::parse(in);
  r.ok = run["run"]["status"] == "ok";
  for (const auto& node : run["nodes"]) {
    if (node["id"] == "eval")
      for (const char* m : kMetrics)
        if (node["records"].contains(m)) r.metrics[m] = node["records"][m].get<double>();
    if (node["id"] == "recon")
      for (const char* m : kReconMetrics)
        if (node["records"].contains(m) && node["records"][m].is_number())
          r.metrics[m] = node["records"][m].get<double>();
  }
  if (r.ok) r.wall_s = run["run"]["total_s"].get<double>();  // the pipeline without process start
  return r;
}

// Time of a query: instance selection, the selected Gaussians (their indicator) and one mask of
// the held-out view, for every class query. The view's QueryView (render cache and instance
// planes) is built once before, as the query node does per view, and timed apart. One untimed
// pass over the queries warms the caches and TBB's thread pool; then `repetitions` passes are
// timed, median / min / max over all of them. The mask through the per-Gaussian sparse product
// (what the query node did before the instance planes) is timed the same way, for the ratio.
nlohmann::json query_timing(const fs::path& graph, const std::vector<std::string>& sets) {
  Registry registry;
  register_builtin_nodes(registry);
  LoadOptions load;
  load.vars["input"] = "embedded:or?seed=0";
  load.sets = sets;
  const LoadResult g = load_graph(graph, registry, load);
  if (!g.ok()) return {{"error", "graph did not load"}};
  const RunResult run = execute(*g.graph, registry, {});
  if (!run.ok()) return {{"error", run.error->str()}};
  // The model and instances the graph's text queries answer on, as the graph wires them.
  const GraphNode* query = g.graph->find("query");
  if (!query) return {{"error", "the graph has no node 'query'"}};
  const auto model = run.values.at(query->inputs.at("model").str()).get<GaussianModel>();
  const auto instances = run.values.at(query->inputs.at("instances").str()).get<InstanceSet>();
  const auto encoder = run.values.at("text.encoder").get<TextEncoder>();
  const auto capture = run.values.at("capture.capture").get<Capture>();
  const View& view = capture->views.at(capture->test_views().at(0));
  const auto cache_start = std::chrono::steady_clock::now();
  const QueryView qv(*model, view.camera, view.pose);
  const double cache_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - cache_start)
          .count();
  TextQueryOptions options;
  for (const auto& [id, name] : capture->classes)
    if (id != 0) options.vocabulary.push_back(name);
  const int repetitions = 5;
  size_t mask_pixels = 0;  // keeps the masks observable
  auto time_queries = [&](bool sparse_product) {
    std::vector<double> ms;
    for (int rep = -1; rep < repetitions; ++rep)
      for (const auto& q : options.vocabulary) {
        const auto t0 = std::chrono::steady_clock::now();
        TextQueryResults r;
        r.queries = {q};
        select_instances(*instances, *encoder, options, r);
        const std::vector<float> selected =
            selection_indicator(model->instance_ids, instances->size(), r.instances[0]);
        const cv::Mat1b mask = sparse_product
                                   ? qv.mask(selected, options.mask_threshold)
                                   : qv.instance_mask(r.instances[0], options.mask_threshold);
        const double t =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count();
        mask_pixels += static_cast<size_t>(cv::countNonZero(mask));
        if (rep >= 0) ms.push_back(t);
      }
    std::sort(ms.begin(), ms.end());
    return ms;
  };
  const std::vector<double> ms = time_queries(false);
  const std::vector<double> product = time_queries(true);
  return {{"view", view.name},
          {"width", view.camera.width},
          {"height", view.camera.height},
          {"gaussians", model->size()},
          {"instances", instances->size()},
          {"query_view_build_ms", cache_ms},
          {"queries_timed", ms.size()},
          {"query_median_ms", ms[ms.size() / 2]},
          {"query_min_ms", ms.front()},
          {"query_max_ms", ms.back()},
          {"sparse_product_median_ms", product[product.size() / 2]},
          {"sparse_product_min_ms", product.front()},
          {"sparse_product_max_ms", product.back()},
          {"mask_pixels", mask_pixels}};
}

std::string svg_chart(const nlohmann::json& variants) {
  const int bar = 18, group = 3 * bar + 24, left = 60, top = 30, height = 220;
  // At least wide enough for the legend and the title.
  const int width = std::max(420, left + group * static_cast<int>(variants.size()) + 20);
  const char* colours[] = {"#4477aa", "#228833", "#ee6677"};
  const char* names[] = {"mIoU", "mLocAcc", "mAcc"};
  Svg svg(width, top + height + 70, 11);
  for (int v = 0; v <= 100; v += 25) {
    const double y = top + height - height * v / 100.0;
    svg.line(left, y, width - 10, y, "#ddd");
    svg.text(left - 6, y + 4, std::to_string(v), "text-anchor='end'");
  }
  int i = 0;
  for (const auto& v : variants) {
    const int x0 = left + 12 + group * i++;
    for (int m = 0; m < 3; ++m) {
      const double mean = v[names[m]]["mean"].is_number() ? v[names[m]]["mean"].get<double>() : 0;
      const double sd = v[names[m]]["std"].is_number() ? v[names[m]]["std"].get<double>() : 0;
      const double h = height * std::clamp(mean, 0.0, 100.0) / 100.0;
      const int x = x0 + m * bar;
      svg.rect(x, top + height - h, bar - 2, h, colours[m]);
      const double y1 = top + height - height * std::clamp(mean + sd, 0.0, 100.0) / 100.0;
      const double y2 = top + height - height * std::clamp(mean - sd, 0.0, 100.0) / 100.0;
      svg.line(x + bar / 2 - 1, y1, x + bar / 2 - 1, y2, "black");
    }
    svg.text(x0 + bar * 3 / 2, top + height + 16, v["variant"].get<std::string>(),
             "text-anchor='middle'");
  }
  for (int m = 0; m < 3; ++m) {
    svg.rect(left + 100 * m, top + height + 34, 10, 10, colours[m]);
    svg.text(left + 100 * m + 14, top + height + 43, names[m]);
  }
  svg.text(left, 18, "LangOR on the embedded OR: mean and std over seeds (percent)");
  return svg.str();
}

}  // namespace

int main(int argc, char** argv) {
  gslift::keep_freed_memory_in_process();
  int seeds = 5;
  // The paper's four ablations, then gslift's own additions taken out (no_cannot_link,
  // no_filter_3d).
  std::vector<std::string> variants = {"langor",       "no_geometry",    "mask_level",  "sigma_07",
                                       "single_round", "no_cannot_link", "no_filter_3d"};
  std::vector<std::string> sets;
  fs::path out = fs::path(GSLIFT_SOURCE_DIR) / "bench/results";
  bool timing = true;
  // The graph whose segmented scene the query timing uses (its nodes named as in langor.yaml);
  // e.g. a copy starting from splat.load, to time queries without re-running reconstruction.
  fs::path query_graph = variant_graph("langor");
  std::string capture_settings;  // appended to embedded:or?seed=S, e.g. "&width=320&height=240"
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--seeds" && has_value) {
      seeds = std::stoi(argv[++i]);
    } else if (a == "--variants" && has_value) {
      variants.clear();
      std::stringstream list(argv[++i]);
      for (std::string v; std::getline(list, v, ',');) variants.push_back(v);
    } else if (a == "--set" && has_value) {
      sets.push_back(argv[++i]);
    } else if (a == "--out" && has_value) {
      out = argv[++i];
    } else if (a == "--capture" && has_value) {
      capture_settings = argv[++i];
    } else if (a == "--query-graph" && has_value) {
      query_graph = argv[++i];
    } else if (a == "--no-timing") {
      timing = false;
    } else {
      std::cerr << "usage: bench_langor [--seeds N] [--variants a,b] [--set NODE.P=V]... "
                   "[--out DIR] [--capture SETTINGS] [--no-timing] [--query-graph GRAPH]\n";
      return 2;
    }
  }
  const fs::path scratch = fs::temp_directory_path() / "gslift_bench_langor";
  nlohmann::json results = nlohmann::json::array();
  std::ostringstream csv;
  csv << "variant,seed,ok,mIoU,mLocAcc,mAcc,mLocAcc_box,mIoU_class,wall_s,peak_mb";
  for (const char* m : kReconMetrics) csv << ',' << m;
  csv << '\n';
  for (const auto& variant : variants) {
    std::map<std::string, std::vector<double>> series;
    nlohmann::json runs = nlohmann::json::array();
    for (int seed = 0; seed < seeds; ++seed) {
      const RunStats r = run_child(variant, seed, capture_settings, sets, scratch);
      std::cerr << "[langor] " << variant << " seed " << seed << (r.ok ? " ok" : " FAILED")
                << " mIoU " << (r.metrics.count("mIoU") ? r.metrics.at("mIoU") : NAN) << " in "
                << r.wall_s << " s, " << r.peak_mb << " MB\n";
      csv << variant << ',' << seed << ',' << r.ok;
      for (const char* m : kMetrics)
        csv << ',' << (r.metrics.count(m) ? std::to_string(r.metrics.at(m)) : "");
      csv << ',' << r.wall_s << ',' << r.peak_mb;
      for (const char* m : kReconMetrics)
        csv << ',' << (r.metrics.count(m) ? std::to_string(r.metrics.at(m)) : "");
      csv << '\n';
      nlohmann::json run = {
          {"seed", seed}, {"ok", r.ok}, {"wall_s", r.wall_s}, {"peak_mb", r.peak_mb}};
      for (const auto& [k, v] : r.metrics) run[k] = v;
      runs.push_back(run);
      if (!r.ok) continue;
      for (const auto& [k, v] : r.metrics) series[k].push_back(v);
      series["wall_s"].push_back(r.wall_s);
      series["peak_mb"].push_back(r.peak_mb);
    }
    nlohmann::json entry = {
        {"variant", variant}, {"graph", variant_graph(variant).filename()}, {"runs", runs}};
    std::vector<std::string> keys = {"mIoU",       "mLocAcc", "mAcc",   "mLocAcc_box",
                                     "mIoU_class", "wall_s",  "peak_mb"};
    keys.insert(keys.end(), std::begin(kReconMetrics), std::end(kReconMetrics));
    for (const std::string& k : keys) {
      if (!series.count(k)) continue;
      const auto [m, s] = mean_std(series[k]);
      entry[k] = {{"mean", std::isnan(m) ? nlohmann::json() : nlohmann::json(m)},
                  {"std", std::isnan(s) ? nlohmann::json() : nlohmann::json(s)}};
    }
    results.push_back(entry);
  }
  nlohmann::json doc = {
      {"benchmark", "langor"}, {"capture", "embedded:or?seed=S (default difficulty)"},
      {"seeds", seeds},        {"hardware_threads", std::thread::hardware_concurrency()},
      {"sets", sets},          {"variants", results}};
  if (timing) doc["query_timing"] = query_timing(query_graph, sets);
  fs::create_directories(out);
  write_file_atomically(out / "langor.json", doc.dump(2) + "\n");
  write_file_atomically(out / "langor.csv", csv.str());
  write_file_atomically(out / "langor.svg", svg_chart(results));
  std::printf("wrote %s/langor.{json,csv,svg}\n", out.string().c_str());
  return 0;
}
