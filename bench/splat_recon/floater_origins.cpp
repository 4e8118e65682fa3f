// floater_origins: where the held-out view's floaters come from (issue 11). For every floater
// pixel (view_geometry.hpp: drawn, median depth more than 10% in front of the ground truth) it
// takes the Gaussian at which the pixel's accumulated opacity reaches 0.5 (the one that sets the
// median depth) and asks each training view's depth prior about its centre (the pixel it projects
// to, relative margin --margin, default 0.1 as free_space.hpp): in observed free space, on the
// observed surface, hidden behind it, or outside the view. It asks the same of the point the pixel
// draws (its ray at the median depth), which for a Gaussian reaching past a silhouette lies away
// from the centre. A floater that some view sees in free space could be carved with the priors;
// one that only sits on or behind observed surfaces cannot. It also sorts the floater pixels by
// the weight their Gaussian draws over every training pixel (line_of_sight_weights, pixels without
// a prior included): under 0.05 no training view sees it, so nothing trains it.
//
//   floater_origins GRAPH [--input CAPTURE] [--set NODE.P=V]... [--margin M]
//                   [--carve F]... [--carve-tolerance T] [--picture PREFIX] [--model-node ID]
//
// --picture PREFIX writes PREFIX<view>.png per held-out view: its ground-truth depth in grey with
// each floater pixel coloured by where the point it draws lies (red: in some training view's
// free space, yellow: on an observed surface, magenta: hidden behind observed surfaces only,
// cyan: outside every training view), to see which objects each kind belongs to.
//
// --carve F prunes the trained model after the fact by the line-of-sight rule (free_space.hpp:
// more than F of a Gaussian's training-view weight drawn over 1 - T of the prior depth, T default
// 0.03) and prints the held-out floaters, holes and PSNR and the training PSNR before and after,
// once per F: what pruning alone does, without the steps that let the model heal.
//
// GRAPH has a node `capture` (ingest.capture) and a node (`model`, or --model-node ID) whose output
// `model` is the reconstruction (splat.load of a run's recon/model.ply, or splat.reconstruct). A
// node's RNG seed depends on its id (runtime/node_seed.hpp): name it `recon` to reproduce the
// reconstruction of graphs/langor.yaml.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "graph/loader.hpp"
#include "nodes/builtin.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/splat/free_space.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "nodes/splat/render_cache.hpp"
#include "nodes/splat/view_geometry.hpp"
#include "runtime/executor.hpp"

using namespace gslift;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: floater_origins GRAPH [--input CAPTURE] [--set NODE.P=V]... [--margin M] "
                 "[--carve F]... [--carve-tolerance T] [--picture PREFIX] [--model-node ID]\n";
    return 2;
  }
  Registry registry;
  register_builtin_nodes(registry);
  LoadOptions load;
  load.vars["input"] = "embedded:or";
  double margin = 0.1;
  std::vector<double> carves;  // --carve may repeat
  double carve_tolerance = 0.03;
  std::string picture, model_node = "model";
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--set") load.sets.push_back(argv[i + 1]);
    if (a == "--input") load.vars["input"] = argv[i + 1];
    if (a == "--margin") margin = std::stod(argv[i + 1]);
    if (a == "--carve") carves.push_back(std::stod(argv[i + 1]));
    if (a == "--carve-tolerance") carve_tolerance = std::stod(argv[i + 1]);
    if (a == "--picture") picture = argv[i + 1];
    if (a == "--model-node") model_node = argv[i + 1];
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
  const auto model = run.values.at(model_node + ".model").get<GaussianModel>();
  std::vector<const View*> train;
  std::vector<cv::Mat1f> prior;
  for (const View& v : capture->views)
    if (!v.held_out) train.push_back(&v), prior.push_back(v.depth.load());

  // Where a world point stands for the training views' depth priors (relative margin `margin`).
  const auto classify = [&](const Eigen::Vector3d& c) -> std::string {
    bool free = false, on = false, hidden = false;
    for (size_t t = 0; t < train.size(); ++t) {
      const Eigen::Vector3d q = train[t]->pose.to_camera(c);
      const Camera& cam = train[t]->camera;
      if (!(q.z() > 0)) continue;
      const double u = cam.fx * q.x() / q.z() + cam.cx, w = cam.fy * q.y() / q.z() + cam.cy;
      if (!(u >= 0 && w >= 0 && u < prior[t].cols && w < prior[t].rows)) continue;
      const float d = prior[t](static_cast<int>(w), static_cast<int>(u));
      if (!(d > 0)) continue;
      if (q.z() < (1 - margin) * d)
        free = true;
      else if (q.z() <= (1 + margin) * d)
        on = true;
      else
        hidden = true;
    }
    return free     ? "in free space of some training view"
           : on     ? "on an observed surface (none sees it free)"
           : hidden ? "hidden behind observed surfaces only"
                    : "outside every training view";
  };

  // Each Gaussian's blending weight over the training pixels, split by where it is drawn: how much
  // the training views see of the Gaussians that set floater pixels (none: hidden or outside).
  std::vector<DepthObservation> observations;
  for (size_t t = 0; t < train.size(); ++t)
    observations.push_back({&train[t]->camera, &train[t]->pose, prior[t]});
  const LineOfSightWeights seen = line_of_sight_weights(*model, observations, margin);
  const auto total_weight = [&](size_t i) {
    return seen.free_space[i] + seen.on_surface[i] + seen.unobserved[i];
  };

  for (const View& view : capture->views) {
    if (!view.held_out) continue;
    const cv::Mat1f gt = view.gt_depth.load();
    RenderSettings weights_only;
    weights_only.rgb = false;
    const RenderCache cache(render(*model, view.camera, view.pose, weights_only));
    const auto& off = cache.pixel_offsets();
    std::map<std::string, int> origin, drawn;  // by the Gaussian's centre; by the drawn point
    std::map<int, int> gaussians;              // floater Gaussian -> pixels it sets
    int surface = 0, floaters = 0;
    double far = 0;
    cv::minMaxLoc(gt, nullptr, &far);
    cv::Mat3b canvas(gt.size());
    for (int y = 0; y < gt.rows; ++y)
      for (int x = 0; x < gt.cols; ++x) {
        const auto g =
            static_cast<uchar>(std::clamp(40 + 200 * gt(y, x) / std::max(far, 1e-6), 0.0, 255.0));
        canvas(y, x) = cv::Vec3b(g, g, g);
      }
    const std::map<std::string, cv::Vec3b> colour = {
        {"in free space of some training view", {0, 0, 255}},
        {"on an observed surface (none sees it free)", {0, 255, 255}},
        {"hidden behind observed surfaces only", {255, 0, 255}},
        {"outside every training view", {255, 255, 0}}};
    for (int y = 0; y < gt.rows; ++y)
      for (int x = 0; x < gt.cols; ++x) {
        const float truth = gt(y, x);
        if (!(truth > 0)) continue;
        ++surface;
        const size_t p = static_cast<size_t>(y) * gt.cols + x;
        float sum = 0;
        int median = -1;
        for (uint32_t e = off[p]; e < off[p + 1]; ++e)
          if ((sum += cache.weights()[e]) >= 0.5f) {
            median = cache.ids()[e];
            break;
          }
        if (median < 0) continue;
        const Eigen::Vector3d c(model->means[median * 3], model->means[median * 3 + 1],
                                model->means[median * 3 + 2]);
        const double z = view.pose.to_camera(c).z();
        if (!(z < 0.9 * truth)) continue;
        ++floaters;
        ++gaussians[median];
        ++origin[classify(c)];
        // The point the pixel draws: on its ray, at the median depth.
        const Eigen::Vector3d ray((x + 0.5 - view.camera.cx) / view.camera.fx,
                                  (y + 0.5 - view.camera.cy) / view.camera.fy, 1.0);
        const std::string kind = classify(view.pose.R.transpose() * (z * ray - view.pose.t));
        ++drawn[kind];
        canvas(y, x) = colour.at(kind);
      }
    if (!picture.empty()) cv::imwrite(picture + view.name + ".png", canvas);
    std::printf("%s: %d floater pixels (%.2f%% of %d surface pixels), set by %zu Gaussians\n",
                view.name.c_str(), floaters, 100.0 * floaters / std::max(surface, 1), surface,
                gaussians.size());
    std::printf(" the median-depth Gaussian's centre:\n");
    for (const auto& [what, n] : origin)
      std::printf("  %-45s %6d px  %5.1f%%\n", what.c_str(), n, 100.0 * n / std::max(floaters, 1));
    std::printf(" the point drawn (the pixel's ray at the median depth):\n");
    for (const auto& [what, n] : drawn)
      std::printf("  %-45s %6d px  %5.1f%%\n", what.c_str(), n, 100.0 * n / std::max(floaters, 1));
    std::printf(" the median-depth Gaussian's weight over every training pixel:\n");
    const double bounds[] = {0.05, 0.5, 5, 50};
    int by_weight[5] = {0, 0, 0, 0, 0};
    for (const auto& [i, n] : gaussians) {
      const double w = total_weight(i);
      by_weight[std::upper_bound(std::begin(bounds), std::end(bounds), w) - std::begin(bounds)] +=
          n;
    }
    const char* names[] = {"< 0.05", "0.05 - 0.5", "0.5 - 5", "5 - 50", ">= 50"};
    for (int b = 0; b < 5; ++b)
      std::printf("  %-45s %6d px  %5.1f%%\n", names[b], by_weight[b],
                  100.0 * by_weight[b] / std::max(floaters, 1));
    std::printf(" where that Gaussian's training-view weight lies (pixel-weighted means):\n");
    double parts[4] = {0, 0, 0, 0};
    int behind_most = 0;
    for (const auto& [i, n] : gaussians) {
      const double total = total_weight(i);
      if (!(total > 0)) continue;
      parts[0] += n * seen.free_space[i] / total;
      parts[1] += n * (seen.on_surface[i] - seen.behind[i]) / total;
      parts[2] += n * seen.behind[i] / total;
      parts[3] += n * seen.unobserved[i] / total;
      if (seen.behind[i] > 0.5 * total) behind_most += n;
    }
    const char* where[] = {"in free space", "on the observed surface", "behind it (seen through)",
                           "at pixels without a prior"};
    for (int b = 0; b < 4; ++b)
      std::printf("  %-45s %5.1f%%\n", where[b], 100.0 * parts[b] / std::max(floaters, 1));
    std::printf("  %-45s %6d px  %5.1f%%\n", "more than half behind", behind_most,
                100.0 * behind_most / std::max(floaters, 1));
    {
      double all = 0, behind_all = 0;
      size_t n_half = 0;
      for (size_t i = 0; i < model->size(); ++i) {
        const double total = total_weight(i);
        all += total;
        behind_all += seen.behind[i];
        if (seen.behind[i] > 0.5 * total && total > 0) ++n_half;
      }
      std::printf(
          " all Gaussians: %.1f%% of the training weight behind; %zu of %zu more than half\n",
          100 * behind_all / std::max(all, 1e-12), n_half, model->size());
    }
  }
  if (!carves.empty()) {
    // Line-of-sight pruning (free_space.hpp): drop the Gaussians that draw more than `carve` of
    // their training-view weight in observed free space; the held-out geometry before and after.
    std::vector<int> train_ids, test_ids = capture->test_views();
    cv::Scalar sum;
    for (size_t t = 0; t < train.size(); ++t) sum += cv::mean(train[t]->rgb.load());
    train_ids = capture->train_views();
    const Eigen::Vector3f bg(float(sum[0] / train.size() / 255), float(sum[1] / train.size() / 255),
                             float(sum[2] / train.size() / 255));
    const LineOfSightWeights los = line_of_sight_weights(*model, observations, carve_tolerance);
    std::vector<GaussianModel> carved;
    for (double carve : carves) {
      const std::vector<char> prune = line_of_sight_prune_mask(los, carve);
      std::vector<size_t> keep;
      for (size_t i = 0; i < prune.size(); ++i)
        if (!prune[i]) keep.push_back(i);
      carved.push_back(model->subset(keep));
    }
    std::vector<const GaussianModel*> models = {model.get()};
    for (const GaussianModel& m : carved) models.push_back(&m);
    for (const GaussianModel* m : models) {
      const ViewGeometry g = mean_view_geometry(*m, *capture, test_ids, train_ids, bg);
      const ViewGeometry t = mean_view_geometry(*m, *capture, train_ids, train_ids, bg);
      std::printf(
          "%s: %zu Gaussians, floaters %.2f%% (away %.2f%%), holes %.2f%% (covered %.2f%%), "
          "held-out %.2f dB, train %.2f dB\n",
          m == model.get() ? "trained" : "carved", m->size(), 100 * g.floaters,
          100 * g.floaters_away_from_discontinuity, 100 * g.holes, 100 * g.holes_covered, g.psnr,
          t.psnr);
    }
  }
  return 0;
}
