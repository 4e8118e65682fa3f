// langor_stages: where each ground-truth class of a synthetic capture is kept or lost, stage by
// stage, in one LangOR run (docs/langor.md "Where the classes are lost").
//
//   langor_stages GRAPH [--input CAPTURE] [--set NODE.P=V]... [--seed S]
//
// Runs GRAPH in this process (a copy of graphs/langor.yaml, possibly starting from splat.load)
// and prints, per ground-truth instance of the capture, from the training views only:
//   masks     training views where a mask overlaps the instance with IoU >= 0.5, and how many of
//             those masks carry the instance's class name;
//   features  share of the instance's pixels whose rendered feature is nearest (cosine) to the
//             centroid of its own instance among all instances' centroids (separability), and the
//             instance it is most often mistaken for;
//   lifting   CVP samples on the instance, their noise share, the cluster holding most of them
//             and that cluster's purity (share of its samples on this instance);
//   assoc     the instances its masks were voted into and those instances' labels;
//   Gaussians share of the instance's training pixels whose heaviest Gaussian is assigned to the
//             instance its masks voted for.
// Nodes must be named as in graphs/langor.yaml (capture, masks, lift, assoc).
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "graph/loader.hpp"
#include "nodes/builtin.hpp"
#include "nodes/scene/instances.hpp"
#include "nodes/scene/lifted_instances.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "nodes/splat/render_cache.hpp"
#include "nodes/splat/training_feature_maps.hpp"
#include "runtime/allocator.hpp"
#include "runtime/executor.hpp"

using namespace gslift;

namespace {

struct InstanceReport {
  int cls = 0;
  int views = 0;        // training views where it has >= 100 pixels
  int mask_views = 0;   // ... and a mask with IoU >= 0.5
  int label_right = 0;  // ... whose label is the class name
  int64_t pixels = 0;   // training pixels (for features)
  int64_t separable = 0;
  std::map<int, int64_t> mistaken;  // gt instance -> pixels nearest to its centroid
  std::map<int, int> samples;       // cluster (-1 noise) -> samples on this instance
  std::map<int, int> voted;         // instance -> masks (IoU >= 0.5) voted into it
  int64_t heaviest = 0, heaviest_right = 0;
};

}  // namespace

int main(int argc, char** argv) {
  gslift::keep_freed_memory_in_process();
  if (argc < 2) {
    std::cerr << "usage: langor_stages GRAPH [--input CAPTURE] [--set NODE.P=V]... [--seed S]\n";
    return 2;
  }
  Registry registry;
  register_builtin_nodes(registry);
  LoadOptions load;
  load.vars["input"] = "embedded:or";
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--set")
      load.sets.push_back(argv[i + 1]);
    else if (a == "--input")
      load.vars["input"] = argv[i + 1];
    else if (a == "--seed")
      load.vars["seed"] = argv[i + 1];
  }
  const LoadResult g = load_graph(argv[1], registry, load);
  if (!g.ok()) {
    for (const auto& d : g.diagnostics) std::cerr << d.message << "\n";
    return 3;
  }
  const RunResult run = execute(*g.graph, registry, {});
  if (!run.ok()) {
    std::cerr << run.error->str() << "\n";
    return 1;
  }
  const auto capture = run.values.at("capture.capture").get<Capture>();
  const auto masks = run.values.at("masks.masks").get<MaskSet>();
  const auto lifted = run.values.at("lift.instances").get<LiftedInstances>();
  const auto instances = run.values.at("assoc.instances").get<InstanceSet>();
  const auto model = run.values.at("assoc.model").get<GaussianModel>();
  const TrainingFeatureMaps maps = render_training_feature_maps(*model, *capture, *masks, false);

  std::map<int, InstanceReport> report;
  for (size_t k = 0; k < maps.maps.size(); ++k) {
    const View& view = capture->views[maps.capture_views[k]];
    const cv::Mat1i gt = view.gt_instance.load();
    const FeatureMap& fm = maps.maps[k];
    const ViewMasks& vm = maps.masks.views[k];
    const std::vector<int>& voted = instances->mask_instance[maps.mask_views[k]];
    // Ground-truth instances of the view and their feature centroids.
    std::map<int, std::vector<double>> centroid;
    std::map<int, int64_t> count;
    for (int y = 0; y < gt.rows; ++y)
      for (int x = 0; x < gt.cols; ++x)
        if (gt(y, x) > 0) {
          auto& c = centroid[gt(y, x)];
          c.resize(fm.dim, 0.0);
          for (int d = 0; d < fm.dim; ++d) c[d] += fm.at(x, y)[d];
          ++count[gt(y, x)];
        }
    for (auto& [id, c] : centroid) {
      double n = 0;
      for (double v : c) n += v * v;
      n = std::sqrt(n);
      for (double& v : c) v /= std::max(n, 1e-12);
    }
    // Heaviest Gaussian per pixel.
    RenderSettings weights_only;
    weights_only.rgb = false;
    const RenderCache cache(render(*model, view.camera, view.pose, weights_only));
    for (const auto& [id, n] : count) {
      if (n < 100) continue;
      InstanceReport& r = report[id];
      r.cls = capture->instance_class.count(id) ? capture->instance_class.at(id) : 0;
      ++r.views;
      const cv::Mat1b gt_mask = (gt == id);
      int best = -1;
      double best_iou = 0.5;
      for (size_t m = 0; m < vm.masks.size(); ++m) {
        const double v = mask_iou(vm.masks[m].pixels, gt_mask);
        if (v >= best_iou) best_iou = v, best = static_cast<int>(m);
      }
      if (best < 0) continue;
      ++r.mask_views;
      r.label_right += vm.masks[best].label == capture->classes.at(r.cls);
      ++r.voted[voted[best]];
      for (int y = 0; y < gt.rows; ++y)
        for (int x = 0; x < gt.cols; ++x) {
          if (gt(y, x) != id) continue;
          const float* f = fm.at(x, y);
          int nearest = -1;
          double nearest_cos = -2;
          for (const auto& [other, c] : centroid) {
            if (count[other] < 100) continue;
            double dot = 0;
            for (int d = 0; d < fm.dim; ++d) dot += c[d] * f[d];
            if (dot > nearest_cos) nearest_cos = dot, nearest = other;
          }
          ++r.pixels;
          if (nearest == id)
            ++r.separable;
          else
            ++r.mistaken[nearest];
          const size_t p = static_cast<size_t>(y) * gt.cols + x;
          const auto& off = cache.pixel_offsets();
          float w = 0;
          int heavy = -1;
          for (uint32_t e = off[p]; e < off[p + 1]; ++e)
            if (cache.weights()[e] > w) w = cache.weights()[e], heavy = cache.ids()[e];
          ++r.heaviest;
          r.heaviest_right +=
              heavy >= 0 && voted[best] >= 0 && model->instance_ids[heavy] == voted[best];
        }
    }
    // Every mask: its label, the ground-truth instance under most of it and the IoU with it.
    for (size_t m = 0; m < vm.masks.size(); ++m) {
      std::map<int, int> under;
      const cv::Mat1b& px = vm.masks[m].pixels;
      for (int y = 0; y < gt.rows; ++y)
        for (int x = 0; x < gt.cols; ++x)
          if (px(y, x)) ++under[gt(y, x)];
      int top = 0, top_n = -1;
      for (const auto& [id, n] : under)
        if (n > top_n) top = id, top_n = n;
      const std::string what = top > 0 ? capture->classes.at(capture->instance_class.at(top))
                                       : std::string("background");
      std::printf("  %s mask %2zu '%s': mostly %s (%d), IoU %.2f, %d px -> instance %d\n",
                  view.name.c_str(), m, vm.masks[m].label.c_str(), what.c_str(), top,
                  top > 0 ? mask_iou(px, gt == top) : 0.0, cv::countNonZero(px), voted[m]);
    }
    for (size_t i = 0; i < lifted->samples.size(); ++i) {
      const SampledPixel& s = lifted->samples[i];
      if (s.view != static_cast<int>(k) || s.x < 0) continue;
      const int id = gt(s.y, s.x);
      if (report.count(id)) ++report[id].samples[lifted->labels[i]];
    }
  }
  std::map<int, int> cluster_size;
  std::map<std::pair<int, int>, int> cluster_on;
  for (const auto& [id, r] : report)
    for (const auto& [c, n] : r.samples) cluster_size[c] += n, cluster_on[{c, id}] = n;

  std::printf("%-20s %4s %9s %7s %6s %-22s %7s %6s %-16s %-40s %6s\n", "class (gt id)", "view",
              "mask/lab", "sep%", "samp", "mistaken for", "noise%", "clust", "purity%",
              "masks voted -> instance:label", "gauss%");
  for (const auto& [id, r] : report) {
    int samples = 0, top = -1, top_n = 0;
    for (const auto& [c, n] : r.samples) {
      samples += n;
      if (c >= 0 && n > top_n) top = c, top_n = n;
    }
    int64_t worst_n = 0;
    int worst = 0;
    for (const auto& [o, n] : r.mistaken)
      if (n > worst_n) worst_n = n, worst = o;
    std::string mistaken =
        worst ? capture->classes.at(capture->instance_class.at(worst)) + " " +
                    std::to_string(100 * worst_n / std::max<int64_t>(r.pixels, 1)) + "%"
              : "-";
    std::string votes;
    for (const auto& [inst, n] : r.voted)
      votes += std::to_string(n) + "->" + std::to_string(inst) + ":" +
               (inst >= 0 ? instances->labels[inst] : std::string("none")) + " ";
    const int noise = r.samples.count(-1) ? r.samples.at(-1) : 0;
    char purity[32] = "-";
    if (top >= 0)
      std::snprintf(purity, sizeof purity, "%d:%.0f%%", top, 100.0 * top_n / cluster_size[top]);
    const std::string name = capture->classes.at(r.cls) + " (" + std::to_string(id) + ")";
    std::printf("%-20s %4d %4d/%-4d %6.1f %6d %-22s %7.1f %6.0f %-16s %-40s %6.1f\n", name.c_str(),
                r.views, r.mask_views, r.label_right,
                100.0 * r.separable / std::max<int64_t>(r.pixels, 1), samples, mistaken.c_str(),
                100.0 * noise / std::max(samples, 1), 100.0 * top_n / std::max(samples, 1), purity,
                votes.c_str(), 100.0 * r.heaviest_right / std::max<int64_t>(r.heaviest, 1));
  }
  // Held-out views: per ground-truth instance, where the heaviest Gaussian of each of its pixels
  // went (instance label, or "-" unassigned).
  for (const View& view : capture->views) {
    if (!view.held_out) continue;
    const cv::Mat1i gt = view.gt_instance.load();
    RenderSettings weights_only;
    weights_only.rgb = false;
    const RenderCache cache(render(*model, view.camera, view.pose, weights_only));
    const auto& off = cache.pixel_offsets();
    std::map<int, std::map<std::string, int>> went;
    for (int y = 0; y < gt.rows; ++y)
      for (int x = 0; x < gt.cols; ++x) {
        const size_t p = static_cast<size_t>(y) * gt.cols + x;
        float w = 0;
        int heavy = -1;
        for (uint32_t e = off[p]; e < off[p + 1]; ++e)
          if (cache.weights()[e] > w) w = cache.weights()[e], heavy = cache.ids()[e];
        const int inst = heavy >= 0 ? model->instance_ids[heavy] : -1;
        ++went[gt(y, x)][inst >= 0 ? std::to_string(inst) + ":" + instances->labels[inst] : "-"];
      }
    for (const auto& [id, labels] : went) {
      int total = 0;
      for (const auto& [l, n] : labels) total += n;
      if (id == 0 || total < 100) continue;
      std::printf("  held-out %s %s (%d), %d px:", view.name.c_str(),
                  capture->classes.at(capture->instance_class.at(id)).c_str(), id, total);
      for (const auto& [l, n] : labels)
        if (n * 20 >= total) std::printf(" %s %.0f%%", l.c_str(), 100.0 * n / total);
      std::printf("\n");
    }
  }
  for (const auto& n : run.nodes)
    for (const auto& [k, v] : n.records)
      if (const double* d = std::get_if<double>(&v))
        std::printf("%s.%s = %g\n", n.id.c_str(), k.c_str(), *d);
  return 0;
}
