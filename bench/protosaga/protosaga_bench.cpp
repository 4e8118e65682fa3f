// protosaga_bench: accuracy, stability and speed of Proto-SaGa and Gaga on the embedded OR.
//
//   protosaga_bench [--seeds N | --seed-list A,B,...] [--views V] [--models DIR] [--out DIR]
//                   [--no-timing] [--view-iterations N] [--dim D] [--lift-iterations N]
//                   [--background black|mean] [--joint] [--joint-only] [--kl LAMBDA]
//                   [--min-areas A,B,...] [--no-cls] [--stem NAME]
//
// For each capture seed S = 0..N-1 (default 5; --seed-list: those seeds in that order) of
// embedded:or?seed=S&views=V (default 5 views, one held out; 8 views hold out two) it reconstructs
// the scene once (or reads DIR/or_vV_sS.ply written by an earlier run with the same --models), then
// runs every variant on that one reconstruction in this process, through the same functions as the
// nodes and with the graphs' defaults:
//   association only, on the training views (Proto-SaGa Table 3): the consistent maps of the
//   memory bank with criteria depth / probability / both (paper overlap score) and Gaga's code
//   (depth, gaga_compat), scored by Gaga's eval.py protocol against the ground-truth instances;
//   end to end, on the held-out views (Table 1 / Table 4): Proto-SaGa (both + prototypes),
//   Proto-SaGa with K-means or a trained classifier (Cls) instead of the prototypes, Proto-SaGa's
//   depth-only association with prototypes, and Gaga (depth gaga_compat + lift + classifier).
// Options add variants: --joint Proto-SaGa (and its K-means and Cls baselines) with the view
// classifiers trained jointly with a reconstruction of its own (Eq. 8; same reconstruction params
// and seed; --joint-only runs it alone, no frozen variant and no timing), --kl Gaga with its 3D KL
// neighbour regulariser at that lambda, --min-areas Proto-SaGa and Gaga (and joint) with each
// minimum label area at inference (label_argmax.hpp); --background sets the reconstruction's
// (graphs' recon.background), --no-cls leaves out the Cls baseline (a lift per seed), --dim the
// view classifiers' feature width D (also of the joint ones). Association time per view is recorded
// for every association. Timing (unless
// --no-timing): the two graphs (graphs/protosaga.yaml, graphs/gaga.yaml) as child `gslift run`
// processes at seed 0 on 2 threads, wall time and peak memory. Writes protosaga[_vV].json and .svg
// into --out (default bench/results).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "base/atomic_file.hpp"
#include "base/random.hpp"
#include "base/statistics.hpp"
#include "base/svg.hpp"
#include "nodes/association/memory_bank.hpp"
#include "nodes/builtin.hpp"
#include "nodes/eval/instance_hungarian.hpp"
#include "nodes/features/label_classifier.hpp"
#include "nodes/features/view_classifiers.hpp"
#include "nodes/inference/label_inference.hpp"
#include "nodes/splat/ply_io.hpp"
#include "runtime/allocator.hpp"
#include "runtime/child_process.hpp"
#include "runtime/executor.hpp"

using namespace gslift;
namespace fs = std::filesystem;

namespace {

struct Scores {
  double miou = 0, precision = 0, recall = 0;
};

Scores percent(const InstanceScores& s) {
  return {100 * s.miou, 100 * s.precision, 100 * s.recall};
}

// The capture, its SAM partitions and a reconstruction, from the first nodes of the graphs.
struct Base {
  std::shared_ptr<const Capture> capture;
  std::shared_ptr<const LabelMapSet> partitions;
  GaussianModel model;
};

Base base_run(const Registry& registry, int seed, int views, const fs::path& models,
              const std::string& background) {
  const std::string input =
      "embedded:or?seed=" + std::to_string(seed) + "&views=" + std::to_string(views);
  const fs::path cached = models / ("or_v" + std::to_string(views) + "_s" + std::to_string(seed) +
                                    (background == "black" ? "" : "_" + background) + ".ply");
  const bool have = !models.empty() && fs::exists(cached);
  const std::string recon =
      have ? "  recon: {type: splat.load, params: {path: \"" + cached.string() + "\"}}\n"
           : "  recon: {type: splat.reconstruct, in: {capture: capture.capture}, params: "
             "{iterations: 500, background: " +
                 background + "}}\n";
  const std::string yaml =
      "graph: protosaga_base\n"
      "nodes:\n"
      "  capture: {type: ingest.capture, params: {path: \"" +
      input +
      "\"}}\n"
      "  sam: {type: ingest.sam_masks, in: {capture: capture.capture}, params: {kind: auto}}\n"
      "  partition: {type: association.sam_partition, in: {capture: capture.capture, masks: "
      "sam.masks}}\n" +
      recon;
  const RunResult run = run_graph_text(yaml, registry);
  if (!run.ok()) throw std::runtime_error(run.error->str());
  Base b;
  b.capture = run.values.at("capture.capture").get<Capture>();
  b.partitions = run.values.at("partition.partitions").get<LabelMapSet>();
  b.model = *run.values.at("recon.model").get<GaussianModel>();
  if (!models.empty() && !have) {
    fs::create_directories(models);
    write_ply(b.model, cached);
  }
  return b;
}

// Per variant and metric, the values over the seeds.
using Series = std::map<std::string, std::map<std::string, std::vector<double>>>;

void add(Series& s, const std::string& variant, const Scores& v) {
  s[variant]["mIoU"].push_back(v.miou);
  s[variant]["precision"].push_back(v.precision);
  s[variant]["recall"].push_back(v.recall);
}

nlohmann::json summary(const Series& series, const std::vector<std::string>& order) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& v : order) {
    nlohmann::json e = {{"variant", v}};
    for (const auto& [metric, values] : series.at(v)) {
      const auto [m, sd] = mean_std(values);
      e[metric] = {{"mean", m}, {"std", sd}, {"values", values}};
    }
    out.push_back(e);
  }
  return out;
}

// Two panels of grouped bars (mIoU, precision, recall; mean with a +-std whisker).
std::string svg_chart(const nlohmann::json& association, const nlohmann::json& end_to_end,
                      const std::string& title) {
  const char* metrics[] = {"mIoU", "precision", "recall"};
  const char* colours[] = {"#4e79a7", "#f28e2b", "#59a14f"};
  const double left = 40, top = 40, height = 220, group = 110, bar = 28;
  const size_t groups = association.size() + end_to_end.size();
  const double width = left + group * groups + 40;
  Svg svg(width, top + height + 90, 11, true);
  for (int v = 0; v <= 100; v += 20) {
    const double y = top + height - height * v / 100.0;
    svg.line(left, y, width - 10, y, "#ddd");
    svg.text(left - 6, y + 4, std::to_string(v), "text-anchor='end'");
  }
  size_t g = 0;
  for (const nlohmann::json* panel : {&association, &end_to_end})
    for (const auto& e : *panel) {
      const double x0 = left + group * g++ + 8;
      for (int m = 0; m < 3; ++m) {
        const double mean = e[metrics[m]]["mean"].get<double>();
        const double sd = e[metrics[m]]["std"].get<double>();
        const double x = x0 + bar * m;
        const double h = height * std::clamp(mean, 0.0, 100.0) / 100.0;
        svg.rect(x, top + height - h, bar - 3, h, colours[m]);
        svg.line(x + bar / 2 - 1.5, top + height - height * std::clamp(mean + sd, 0.0, 100.0) / 100,
                 x + bar / 2 - 1.5, top + height - height * std::clamp(mean - sd, 0.0, 100.0) / 100,
                 "black");
      }
      svg.text(x0 + bar * 1.5, top + height + 16, e["variant"].get<std::string>(),
               "text-anchor='middle'");
    }
  const double split = left + group * association.size();
  svg.line(split, top - 10, split, top + height + 24, "#888", "stroke-dasharray='4 3'");
  svg.text(left, top + height + 40, "association, training views (Table 3)");
  svg.text(split + 6, top + height + 40, "end to end, held-out views");
  for (int m = 0; m < 3; ++m) {
    svg.rect(left + 90 * m, top + height + 58, 10, 10, colours[m]);
    svg.text(left + 90 * m + 14, top + height + 67, metrics[m]);
  }
  svg.text(left, 18, title);
  return svg.str();
}

}  // namespace

int main(int argc, char** argv) {
  keep_freed_memory_in_process();
  int seeds = 5, views = 5, view_iterations = ViewClassifierOptions{}.iterations,
      dim = ViewClassifierOptions{}.dim, lift_iterations = LabelClassifierOptions{}.iterations;
  bool timing = true, joint = false, cls = true, frozen = true;
  double kl = 0;
  std::vector<double> min_areas;
  std::vector<int> seed_list;
  std::string background = "black", stem_name;
  fs::path out = fs::path(GSLIFT_SOURCE_DIR) / "bench/results", models;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      return argv[++i];
    };
    if (a == "--seeds")
      seeds = std::stoi(next());
    else if (a == "--seed-list") {
      std::stringstream list(next());
      for (std::string v; std::getline(list, v, ',');) seed_list.push_back(std::stoi(v));
    } else if (a == "--views")
      views = std::stoi(next());
    else if (a == "--models")
      models = next();
    else if (a == "--out")
      out = next();
    else if (a == "--view-iterations")
      view_iterations = std::stoi(next());
    else if (a == "--dim")
      dim = std::stoi(next());
    else if (a == "--lift-iterations")
      lift_iterations = std::stoi(next());
    else if (a == "--no-timing")
      timing = false;
    else if (a == "--background")
      background = next();
    else if (a == "--joint")
      joint = true;
    else if (a == "--kl")
      kl = std::stod(next());
    else if (a == "--min-areas") {
      std::stringstream list(next());
      for (std::string v; std::getline(list, v, ',');) min_areas.push_back(std::stod(v));
    } else if (a == "--no-cls")
      cls = false;
    else if (a == "--joint-only")
      joint = true, frozen = false, timing = false;
    else if (a == "--stem")
      stem_name = next();
    else {
      std::cerr
          << "usage: protosaga_bench [--seeds N | --seed-list A,B,...] [--views V] [--models DIR] "
             "[--out DIR] "
             "[--no-timing] [--view-iterations N] [--dim D] [--lift-iterations N] [--background "
             "black|mean] [--joint] [--joint-only] [--kl LAMBDA] [--min-areas A,B,...] [--no-cls] "
             "[--stem NAME]\n";
      return 2;
    }
  }
  if (seed_list.empty())
    for (int seed = 0; seed < seeds; ++seed) seed_list.push_back(seed);
  Registry registry;
  register_builtin_nodes(registry);

  Series assoc, e2e;
  std::map<std::string, std::vector<double>> ms_per_view, seconds;
  for (const int seed : seed_list) {
    std::fprintf(stderr, "[protosaga] seed %d: capture and reconstruction\n", seed);
    const Base b = base_run(registry, seed, views, models, background);
    const Capture& capture = *b.capture;
    const std::vector<int> test = capture.test_views();

    ViewClassifierOptions vo;
    vo.seed = stream_seed(seed, "bench.view_classifiers");
    vo.iterations = view_iterations;
    vo.dim = dim;
    auto scored = [&](const LabelMapSet& labels) {
      return percent(score_label_maps(labels, capture));
    };
    auto area_name = [](const std::string& v, double a) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%s_area%g", v.c_str(), a);
      return std::string(buf);
    };
    std::vector<std::string> printed;
    // Gaga's lift (a classifier on features trained against consistent labels) on `model`.
    auto lift_on = [&](const GaussianModel& model, const LabelMapSet& labels, double kl_lambda) {
      LabelClassifierOptions lo;
      lo.seed = stream_seed(seed, "bench.label_classifier");
      lo.iterations = lift_iterations;
      lo.kl.lambda = kl_lambda;
      LabelClassifierResult r = train_label_classifier(model, capture, labels, lo);
      seconds[kl_lambda > 0 ? "label_classifier_kl" : "label_classifier"].push_back(r.seconds);
      return r;
    };
    if (frozen) {  // --joint-only: the frozen variants are left out
      const ViewClassifierResult vc = train_view_classifiers(b.model, capture, *b.partitions, vo);
      seconds["view_classifiers"].push_back(vc.seconds);

      auto associate = [&](AssociationCriteria c, bool compat) {
        MemoryBankOptions o;
        o.criteria = c;
        o.gaga_compat = compat;
        return associate_masks(vc.model, capture, *b.partitions, &vc.classifiers, o);
      };
      std::map<std::string, AssociationResult> a;
      a["depth"] = associate(AssociationCriteria::Depth, false);
      a["probability"] = associate(AssociationCriteria::Probability, false);
      a["both"] = associate(AssociationCriteria::Both, false);
      a["gaga"] = associate(AssociationCriteria::Depth, true);
      for (const auto& [name, r] : a) {
        add(assoc, name, percent(score_label_maps(r.consistent, capture)));
        for (const double ms : r.view_ms) ms_per_view[name].push_back(ms);
      }

      auto lift = [&](const LabelMapSet& labels, double kl_lambda) {
        return lift_on(b.model, labels, kl_lambda);
      };
      auto lifted = [&](const LabelMapSet& labels) {
        const LabelClassifierResult r = lift(labels, 0);
        return infer_labels_by_classifier(r.model, capture, r.classifier, test);
      };
      printed = {"protosaga", "kmeans", "depth_proto", "gaga"};
      if (cls) printed.push_back("cls");
      add(e2e, "protosaga",
          scored(infer_labels_by_prototypes(vc.model, capture, a["both"].consistent, test,
                                            PrototypeClassifier::Averaged, seed)));
      add(e2e, "kmeans",
          scored(infer_labels_by_prototypes(vc.model, capture, a["both"].consistent, test,
                                            PrototypeClassifier::KMeans, seed)));
      add(e2e, "depth_proto",
          scored(infer_labels_by_prototypes(vc.model, capture, a["depth"].consistent, test,
                                            PrototypeClassifier::Averaged, seed)));
      if (cls) add(e2e, "cls", scored(lifted(a["both"].consistent)));
      const LabelClassifierResult gaga = lift(a["gaga"].consistent, 0);
      add(e2e, "gaga",
          scored(infer_labels_by_classifier(gaga.model, capture, gaga.classifier, test)));
      for (const double area : min_areas) {
        add(e2e, area_name("protosaga", area),
            scored(infer_labels_by_prototypes(vc.model, capture, a["both"].consistent, test,
                                              PrototypeClassifier::Averaged, seed, area)));
        add(e2e, area_name("gaga", area),
            scored(infer_labels_by_classifier(gaga.model, capture, gaga.classifier, test, area)));
        printed.push_back(area_name("protosaga", area));
        printed.push_back(area_name("gaga", area));
      }
      if (kl > 0) {
        const LabelClassifierResult r = lift(a["gaga"].consistent, kl);
        add(e2e, "gaga_kl",
            scored(infer_labels_by_classifier(r.model, capture, r.classifier, test)));
        printed.push_back("gaga_kl");
      }
    }
    if (joint) {
      ViewClassifierOptions jo = vo;
      jo.training = FeatureTraining::Joint;
      jo.recon.iterations = 500;
      jo.recon.background = parse_enum(background, background_names(), "--background");
      const ViewClassifierResult jc =
          train_view_classifiers_jointly(capture, *b.partitions, jo, [&](const TrainingStep& s) {
            if (s.step % 100 == 0)
              std::fprintf(stderr, "[protosaga] seed %d joint step %d / %d\n", seed, s.step,
                           s.total);
          });
      seconds["joint_reconstruction"].push_back(jc.seconds);
      MemoryBankOptions o;
      o.criteria = AssociationCriteria::Both;
      const AssociationResult ja =
          associate_masks(jc.model, capture, *b.partitions, &jc.classifiers, o);
      add(assoc, "both_joint", percent(score_label_maps(ja.consistent, capture)));
      std::fprintf(stderr, "[protosaga] seed %d association both_joint mIoU %.1f precision %.1f\n",
                   seed, assoc["both_joint"]["mIoU"].back(),
                   assoc["both_joint"]["precision"].back());
      add(e2e, "protosaga_joint",
          scored(infer_labels_by_prototypes(jc.model, capture, ja.consistent, test,
                                            PrototypeClassifier::Averaged, seed)));
      printed.push_back("protosaga_joint");
      // The baselines of Table 4 on the joint features and labels: K-means over the prototypes,
      // and a classifier lifted on the joint model (Cls).
      add(e2e, "kmeans_joint",
          scored(infer_labels_by_prototypes(jc.model, capture, ja.consistent, test,
                                            PrototypeClassifier::KMeans, seed)));
      printed.push_back("kmeans_joint");
      if (cls) {
        const LabelClassifierResult r = lift_on(jc.model, ja.consistent, 0);
        add(e2e, "cls_joint",
            scored(infer_labels_by_classifier(r.model, capture, r.classifier, test)));
        printed.push_back("cls_joint");
      }
      for (const double area : min_areas) {
        add(e2e, area_name("protosaga_joint", area),
            scored(infer_labels_by_prototypes(jc.model, capture, ja.consistent, test,
                                              PrototypeClassifier::Averaged, seed, area)));
        printed.push_back(area_name("protosaga_joint", area));
      }
      std::fprintf(stderr, "[protosaga] seed %d joint: train PSNR %.2f test PSNR %.2f\n", seed,
                   jc.recon->train_psnr, jc.recon->test_psnr);
    }
    for (const std::string& v : printed)
      std::fprintf(stderr, "[protosaga] seed %d %-22s mIoU %.1f precision %.1f recall %.1f\n", seed,
                   v.c_str(), e2e[v]["mIoU"].back(), e2e[v]["precision"].back(),
                   e2e[v]["recall"].back());
  }

  nlohmann::json doc;
  doc["capture"] = "embedded:or?seed=S&views=" + std::to_string(views);
  doc["seeds"] = seed_list;
  doc["view_iterations"] = view_iterations;
  doc["dim"] = dim;
  doc["lift_iterations"] = lift_iterations;
  doc["background"] = background;
  std::vector<std::string> assoc_order;
  for (const char* v : {"depth", "probability", "both", "gaga", "both_joint"})
    if (assoc.count(v)) assoc_order.push_back(v);
  std::vector<std::string> e2e_order;
  for (const char* v : {"protosaga", "kmeans", "cls", "depth_proto", "gaga"})
    if (e2e.count(v)) e2e_order.push_back(v);
  for (const auto& [name, values] : e2e)
    if (std::find(e2e_order.begin(), e2e_order.end(), name) == e2e_order.end())
      e2e_order.push_back(name);
  doc["association"] = summary(assoc, assoc_order);
  doc["end_to_end"] = summary(e2e, e2e_order);
  for (const auto& [name, v] : ms_per_view) {
    const auto [m, sd] = mean_std(v);
    doc["association_ms_per_view"][name] = {{"mean", m}, {"std", sd}};
  }
  for (const auto& [name, v] : seconds) {
    const auto [m, sd] = mean_std(v);
    doc["stage_seconds"][name] = {{"mean", m}, {"std", sd}};
  }
  if (timing) {
    for (const char* graph : {"protosaga", "gaga"}) {
      const fs::path run_out =
          fs::temp_directory_path() / ("protosaga_bench_" + std::string(graph));
      fs::remove_all(run_out);
      const ChildRun r = run_child_process(
          {GSLIFT_BINARY, "run",
           (fs::path(GSLIFT_SOURCE_DIR) / "graphs" / (std::string(graph) + ".yaml")).string(),
           "--input", "embedded:or?seed=0&views=" + std::to_string(views), "--threads", "2",
           "--out", run_out.string(), "--log-level", "warn", "--no-cache"});
      doc["timing"][graph] = {
          {"ok", r.started && WIFEXITED(r.status) && WEXITSTATUS(r.status) == 0},
          {"wall_s", r.wall_s},
          {"peak_mb", r.peak_mb}};
    }
  }
  const std::string stem = !stem_name.empty() ? stem_name
                           : views == 5       ? "protosaga"
                                              : "protosaga_v" + std::to_string(views);
  fs::create_directories(out);
  write_file_atomically(out / (stem + ".json"), doc.dump(2) + "\n");
  write_file_atomically(out / (stem + ".svg"),
                        svg_chart(doc["association"], doc["end_to_end"],
                                  "Proto-SaGa and Gaga on the embedded OR (" +
                                      std::to_string(views) + " views): mean +- std over " +
                                      std::to_string(seed_list.size()) + " seeds (percent)"));
  std::printf("%s\n", doc.dump(2).c_str());
  return 0;
}
