// bench_detector_fusion: accuracy, stability and speed of the detector-priors pipeline (paper 002)
// on the embedded operating room.
//
//   bench_detector_fusion [--seeds N] [--views 5,8] [--out DIR] [--capture "&width=320&height=240"]
//                         [--set NODE.P=V]...
//
// For every view count V and seed S it runs graphs/detector_fusion.yaml in this process on
// embedded:or?seed=S&views=V and reads GA / CA / CP of each stage from the graph's eval nodes
// (3D source alone, priors alone, single-view fusion, + multi-view, + smoothing), with the wall
// time of the whole graph and of each stage. On the default 5-view capture it then runs the
// ablations on the same LangOR outputs by calling the stages' functions (the ablation graphs in
// graphs/ablations/detector_fusion/ compute the same, each re-running LangOR): 3D source alone and
// priors alone through multi-view fusion and smoothing, no multi-view, certain priors
// (confidence 1, no cap), RGB-only GrabCut, box priors, priors in detector order, priors without
// GrabCut; and the size-ordering check: the
// recall of the supporting surfaces (operating table, instrument table) and of what stands on
// them (patient) in the priors alone, sorted by size and in detector order. Writes
// detector_fusion.json and detector_fusion_<V>views.svg into --out (default bench/results).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/atomic_file.hpp"
#include "base/statistics.hpp"
#include "base/svg.hpp"
#include "nodes/boxes/grabcut_priors.hpp"
#include "nodes/builtin.hpp"
#include "nodes/eval/semantic_eval.hpp"
#include "nodes/fusion/bayesian_fusion.hpp"
#include "nodes/fusion/cluster_smoothing.hpp"
#include "nodes/fusion/multiview_fusion.hpp"
#include "runtime/executor.hpp"

using namespace gslift;
namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

const char* kStages[] = {"eval_source3d", "eval_priors", "eval_fused", "eval_multiview",
                         "semantic"};
const char* kStageNames[] = {"3D source", "priors", "fused (single view)", "+ multi-view",
                             "+ smoothing (final)"};
const char* kTimed[] = {"recon", "priors", "source3d", "fused", "multiview", "smooth"};
const char* kSupports[] = {"operating table", "instrument table", "patient"};

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// GA / CA / CP over all views, the training views and the held-out views.
Json scores_json(const SemanticEvaluation& e) {
  Json j;
  for (const auto& [name, c] : {std::pair<const char*, const Confusion*>{"all", &e.all},
                                {"train", &e.train},
                                {"test", &e.test}}) {
    const SemanticScores s = semantic_scores(*c);
    j[name] = {{"GA", s.ga}, {"CA", s.ca}, {"CP", s.cp}};
  }
  return j;
}

Json records_json(const NodeRecord& node) {
  Json j;
  for (const char* set : {"all", "train", "test"})
    for (const char* m : {"GA", "CA", "CP"}) {
      const std::string key = std::string(set) == "all" ? m : std::string(set) + "/" + m;
      j[set][m] = std::get<double>(node.records.at(key));
    }
  return j;
}

// One seed's ablations on the graph's outputs.
Json ablations(const RunResult& run) {
  const auto capture = run.values.at("capture.capture").get<Capture>();
  const auto boxes = run.values.at("boxes.clusters").get<BoxSet>();
  const auto masks = run.values.at("masks.masks").get<MaskSet>();
  const auto source3d = run.values.at("source3d.semantics").get<SemanticMaps>();
  const auto priors = run.values.at("priors.priors").get<SemanticMaps>();
  const auto fused = run.values.at("fused.semantics").get<SemanticMaps>();
  const MultiviewFusionOptions mv;
  const SupervoxelOptions sv;
  auto finish = [&](const SemanticMaps& m) {
    return scores_json(evaluate_semantics(
        smooth_cluster_maps(fuse_multiview_maps(m, *capture, mv), *capture, sv), *capture));
  };
  Json out;
  out["source3d_only"] = finish(*source3d);
  out["priors_only"] = finish(*priors);
  out["no_multiview"] =
      scores_json(evaluate_semantics(smooth_cluster_maps(*fused, *capture, sv), *capture));
  // Certain priors (max_confidence 1): every box of the embedded OR's VLM scores 1, so they are
  // the graph's priors with confidence 1 wherever they paint (recomputed when a score is not 1).
  bool all_one = true;
  for (const ViewBoxes& vb : boxes->views)
    for (const Box& b : vb.boxes) all_one = all_one && b.score == 1.f;
  SemanticMaps certain = *priors;
  if (all_one) {
    for (SemanticView& v : certain.views) {
      cv::Mat1f confidence = cv::Mat1f::zeros(v.labels.size());
      confidence.setTo(1.f, v.labels >= 0);
      v = label_confidence_view(v.view, v.labels, confidence, certain.class_count());
    }
  } else {
    GrabcutPriorOptions o;
    o.max_confidence = 1.f;
    certain = detector_prior_maps(*capture, *boxes, *masks, o).priors;
  }
  out["certain_priors"] = finish(fuse_bayesian_maps(*source3d, certain));
  // Prior variants: refined again, fused with the same 3D source, multi-view, smoothing.
  const std::vector<std::pair<std::string, std::function<void(GrabcutPriorOptions&)>>> variants = {
      {"rgb_grabcut", [](GrabcutPriorOptions& o) { o.grabcut.use_depth = false; }},
      {"box_priors", [](GrabcutPriorOptions& o) { o.kind = PriorKind::Box; }},
      {"unsorted_priors", [](GrabcutPriorOptions& o) { o.sort_by_size = false; }},
      {"no_grabcut", [](GrabcutPriorOptions& o) { o.refine = false; }},
  };
  SemanticEvalOptions as_background;
  as_background.unlabelled_as_background = true;
  SemanticMaps unsorted_priors;
  for (const auto& [name, change] : variants) {
    GrabcutPriorOptions o;
    change(o);
    const auto t0 = std::chrono::steady_clock::now();
    const DetectorPriorMaps p = detector_prior_maps(*capture, *boxes, *masks, o);
    const double priors_s = seconds_since(t0);
    out[name] = finish(fuse_bayesian_maps(*source3d, p.priors));
    out[name]["priors_s"] = priors_s;
    out[name]["priors_alone"] = scores_json(evaluate_semantics(p.priors, *capture, as_background));
    if (name == "unsorted_priors") unsorted_priors = p.priors;
  }
  // Size ordering: per-class recall of the priors alone, sorted (the graph's) and in detector
  // order (the unsorted variant's, whose GrabCut work is the graph's: only the painting order
  // differs, so its time is also the standalone time of the graph's priors).
  for (const auto& [name, maps] :
       {std::pair<std::string, const SemanticMaps*>{"sorted", priors.get()},
        {"unsorted", &unsorted_priors}}) {
    const SemanticScores s =
        semantic_scores(evaluate_semantics(*maps, *capture, as_background).all);
    for (const char* cls : kSupports) {
      const int k = class_index(maps->classes, cls);
      if (k >= 0 && s.classes[k].present)
        out["size_ordering"][name][cls] = 100 * s.classes[k].recall;
    }
  }
  out["grabcut_per_view_s"] =
      out["unsorted_priors"]["priors_s"].get<double>() / capture->views.size();
  return out;
}

// Mean and std over the runs of every number at the same path (objects are walked, numbers
// collected).
void collect(const Json& j, const std::string& path,
             std::map<std::string, std::vector<double>>& out) {
  if (j.is_number()) {
    out[path].push_back(j.get<double>());
  } else if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it)
      collect(it.value(), path.empty() ? it.key() : path + "/" + it.key(), out);
  }
}

Json summarise(const std::vector<Json>& runs) {
  std::map<std::string, std::vector<double>> series;
  for (const Json& r : runs) collect(r, "", series);
  Json out;
  for (const auto& [path, v] : series) {
    const auto [m, s] = mean_std(v);
    out[path] = {{"mean", m}, {"std", s}, {"n", v.size()}};
  }
  return out;
}

// Bars of CA (all views and held-out views) per stage and ablation, with std whiskers.
std::string svg_chart(const std::vector<std::pair<std::string, std::string>>& bars,
                      const Json& summary, const std::string& title) {
  const int bar = 16, group = 2 * bar + 14, left = 50, top = 30, height = 220;
  const int width = std::max(520, left + group * static_cast<int>(bars.size()) + 20);
  const char* colours[] = {"#4477aa", "#ee6677"};
  const char* sets[] = {"all", "test"};
  Svg svg(width, top + height + 150, 11, true);
  for (int v = 0; v <= 100; v += 25) {
    const double y = top + height - height * v / 100.0;
    svg.line(left, y, width - 10, y, "#ddd");
    svg.text(left - 6, y + 4, std::to_string(v), "text-anchor='end'");
  }
  int i = 0;
  for (const auto& [label, prefix] : bars) {
    const int x0 = left + 8 + group * i++;
    for (int s = 0; s < 2; ++s) {
      const std::string key = prefix + "/" + sets[s] + "/CA";
      if (!summary.contains(key)) continue;
      const double mean = summary[key]["mean"].get<double>();
      const double sd = summary[key]["std"].get<double>();
      const double h = height * std::clamp(mean, 0.0, 100.0) / 100.0;
      const int x = x0 + s * bar;
      svg.rect(x, top + height - h, bar - 2, h, colours[s]);
      const double y1 = top + height - height * std::clamp(mean + sd, 0.0, 100.0) / 100.0;
      const double y2 = top + height - height * std::clamp(mean - sd, 0.0, 100.0) / 100.0;
      svg.line(x + bar / 2 - 1, y1, x + bar / 2 - 1, y2, "black");
    }
    const double tx = x0 + bar, ty = top + height + 10;
    svg.text(tx, ty, label,
             "text-anchor='end' transform='rotate(-45 " + Svg::number(tx) + " " + Svg::number(ty) +
                 ")'");
  }
  svg.rect(left, top + height + 122, 10, 10, colours[0]);
  svg.text(left + 14, top + height + 131, "CA, all views");
  svg.rect(left + 130, top + height + 122, 10, 10, colours[1]);
  svg.text(left + 144, top + height + 131, "CA, held-out views");
  svg.text(left, 18, title);
  return svg.str();
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 5;
  std::vector<int> view_counts = {5, 8};
  std::vector<std::string> sets;
  fs::path out = fs::path(GSLIFT_SOURCE_DIR) / "bench/results";
  std::string capture_settings;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--seeds" && has_value) {
      seeds = std::stoi(argv[++i]);
    } else if (a == "--views" && has_value) {
      view_counts.clear();
      std::stringstream list(argv[++i]);
      for (std::string v; std::getline(list, v, ',');) view_counts.push_back(std::stoi(v));
    } else if (a == "--set" && has_value) {
      sets.push_back(argv[++i]);
    } else if (a == "--out" && has_value) {
      out = argv[++i];
    } else if (a == "--capture" && has_value) {
      capture_settings = argv[++i];
    } else {
      std::cerr << "usage: bench_detector_fusion [--seeds N] [--views 5,8] [--set NODE.P=V]... "
                   "[--out DIR] [--capture SETTINGS]\n";
      return 2;
    }
  }
  Registry registry;
  register_builtin_nodes(registry);
  const fs::path graph = fs::path(GSLIFT_SOURCE_DIR) / "graphs/detector_fusion.yaml";
  Json captures = Json::array();
  for (int views : view_counts) {
    std::vector<Json> runs;
    for (int seed = 0; seed < seeds; ++seed) {
      LoadOptions load;
      load.vars["input"] = "embedded:or?seed=" + std::to_string(seed) +
                           "&views=" + std::to_string(views) + capture_settings;
      load.sets = sets;
      const LoadResult g = load_graph(graph, registry, load);
      if (!g.ok()) {
        std::cerr << "[detector_fusion] graph did not load\n";
        return 1;
      }
      const RunResult run = execute(*g.graph, registry, {});
      if (!run.ok()) {
        std::cerr << "[detector_fusion] views " << views << " seed " << seed
                  << " FAILED: " << run.error->str() << "\n";
        continue;
      }
      Json r = {{"seed", seed}, {"total_s", run.total_s}};
      for (const char* stage : kStages) r["stages"][stage] = records_json(*run.node(stage));
      for (const char* id : kTimed) {
        const NodeRecord* n = run.node(id);
        r["time_s"][id] = n->end_s - n->start_s;
      }
      r["time_s"]["priors_per_view"] = r["time_s"]["priors"].get<double>() / views;
      r["painted"] = std::get<double>(run.node("priors")->records.at("painted"));
      if (views == 5) r["ablations"] = ablations(run);
      std::cerr << "[detector_fusion] views " << views << " seed " << seed << ": CA 3D "
                << r["stages"]["eval_source3d"]["all"]["CA"] << " fused "
                << r["stages"]["eval_fused"]["all"]["CA"] << " final "
                << r["stages"]["semantic"]["all"]["CA"] << " (graph " << run.total_s << " s)\n";
      runs.push_back(r);
    }
    Json runs_json = Json::array();
    for (const auto& r : runs) runs_json.push_back(r);
    const Json summary = summarise(runs);
    captures.push_back(
        {{"capture", "embedded:or?seed=S&views=" + std::to_string(views) + capture_settings},
         {"views", views},
         {"runs", runs_json},
         {"summary", summary}});
    std::vector<std::pair<std::string, std::string>> bars;
    for (size_t s = 0; s < std::size(kStages); ++s)
      bars.push_back({kStageNames[s], std::string("stages/") + kStages[s]});
    if (views == 5)
      for (const char* a : {"source3d_only", "priors_only", "no_multiview", "certain_priors",
                            "rgb_grabcut", "box_priors", "unsorted_priors", "no_grabcut"})
        bars.push_back({std::string("ablation: ") + a, std::string("ablations/") + a});
    fs::create_directories(out);
    write_file_atomically(out / ("detector_fusion_" + std::to_string(views) + "views.svg"),
                          svg_chart(bars, summary,
                                    "Detector priors on the embedded OR, " + std::to_string(views) +
                                        " views: CA, mean and std over " +
                                        std::to_string(runs.size()) + " seeds (percent)"));
  }
  const Json doc = {{"benchmark", "detector_fusion"},
                    {"graph", "graphs/detector_fusion.yaml"},
                    {"seeds", seeds},
                    {"hardware_threads", std::thread::hardware_concurrency()},
                    {"sets", sets},
                    {"captures", captures}};
  fs::create_directories(out);
  write_file_atomically(out / "detector_fusion.json", doc.dump(2) + "\n");
  std::printf("wrote %s/detector_fusion.json and detector_fusion_<V>views.svg\n",
              out.string().c_str());
  return 0;
}
