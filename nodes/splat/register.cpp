#include "nodes/splat/register.hpp"

#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "base/atomic_file.hpp"
#include "nodes/scene/caption_strip.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/image_io.hpp"
#include "nodes/scene/view_poses.hpp"
#include "nodes/splat/channel_images.hpp"
#include "nodes/splat/ply_io.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "nodes/splat/reconstruct.hpp"
#include "nodes/splat/reconstruction_check.hpp"
#include "nodes/splat/view_geometry.hpp"

namespace gslift {
namespace {

PortSpec capture_port(std::vector<CaptureNeed> needs) {
  return {"capture", PortTypeName<Capture>::value, "posed views with an optional depth prior",
          false, std::move(needs)};
}

PortSpec model_port(const std::string& doc) {
  return {"model", PortTypeName<GaussianModel>::value, doc};
}

// splat.reconstruct's params: a recipe, the reconstruction's, then when its result counts as
// none.
struct ReconstructNodeParams {
  Recipe recipe = Recipe::None;  // resolved by the graph (ParamSpec::presets), not read here
  ReconstructOptions recon;
  double min_train_psnr = kDefaultMinTrainPsnr;
};

const ParamTable<ReconstructNodeParams>& reconstruct_node_param_table() {
  using P = ReconstructNodeParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .add("recipe", &P::recipe, recipe_names(),
               "a named group of the params below, set where the graph leaves them unset: none, or "
               "depth_prior (a capture with a depth prior: the line-of-sight prior, pruning "
               "against the prior, the edge-extent term and the mean-colour background, "
               "bench/splat_recon/README.md)")
          .presets(recipe_presets())
          .nest(&P::recon, reconstruct_param_table())
          .add("min_train_psnr", &P::min_train_psnr,
               "fail when the final train PSNR (dB) is under this floor: a model that explains its "
               "own training views this badly is no result; 0 = no floor (an empty model always "
               "fails)",
               0);
  return table;
}

// The final loss and each term's (loss_<term>), the phases' seconds and the held-out geometry.
void record_losses_and_geometry(NodeContext& ctx, const ReconstructResult& r) {
  ctx.record("loss_total", r.final_loss.total);
  for (const auto& [term, value] : r.final_loss.terms) ctx.record("loss_" + term, value);
  ctx.record("train_psnr", r.train_psnr);
  if (!std::isnan(r.test_psnr)) ctx.record("test_psnr", r.test_psnr);
  if (!r.test_geometry) return;
  // NaN (no such pixel) is left out: run.json holds numbers only.
  const ViewGeometry& g = *r.test_geometry;
  const std::pair<const char*, double> geometry[] = {
      {"test_psnr_covered", g.psnr_covered},
      {"test_coverage", g.coverage},
      {"test_depth_abs_rel_median", g.depth_abs_rel_median},
      {"test_depth_within_5pct", g.depth_within_5pct},
      {"test_floaters", g.floaters},
      {"test_floaters_covered", g.floaters_covered},
      {"test_floaters_expected_depth", g.floaters_expected_depth},
      {"test_floaters_at_discontinuity", g.floaters_at_discontinuity},
      {"test_floaters_away_from_discontinuity", g.floaters_away_from_discontinuity},
      {"test_holes", g.holes},
      {"test_holes_covered", g.holes_covered}};
  for (const auto& [key, value] : geometry)
    if (std::isfinite(value)) ctx.record(key, value);
}

ViewPoses view_poses(const Capture& capture, const std::vector<Pose>& poses) {
  ViewPoses out;
  for (size_t v = 0; v < capture.views.size(); ++v) {
    out.views.push_back(capture.views[v].name);
    out.poses.push_back(poses[v]);
  }
  return out;
}

// How far refinement moved the poses: mean and largest rotation (degrees) and camera-centre
// shift (capture units), over the training and over the held-out views.
void record_pose_changes(NodeContext& ctx, const Capture& capture, const std::vector<Pose>& poses) {
  for (const auto& [set, views] :
       {std::pair{"train", capture.train_views()}, std::pair{"held_out", capture.test_views()}}) {
    if (views.empty()) continue;
    double deg = 0, deg_max = 0, centre = 0, centre_max = 0;
    for (int v : views) {
      const PoseChange c = pose_change(capture.views[v].pose, poses[v]);
      deg += c.degrees / views.size();
      centre += c.centre / views.size();
      deg_max = std::max(deg_max, c.degrees);
      centre_max = std::max(centre_max, c.centre);
    }
    const std::string prefix = std::string("pose_change/") + set + "/";
    ctx.record(prefix + "degrees_mean", deg);
    ctx.record(prefix + "degrees_max", deg_max);
    ctx.record(prefix + "centre_mean", centre);
    ctx.record(prefix + "centre_max", centre_max);
  }
}

void run_reconstruct(NodeContext& ctx, ReconstructNodeParams p) {
  ReconstructOptions& o = p.recon;
  o.seed = ctx.seed();
  ReconstructResult r =
      reconstruct(*ctx.input<Capture>("capture"), o, [&](const TrainingStep& step, size_t) {
        ctx.check_cancelled();
        ctx.progress(step);
      });
  ctx.record("gaussians", static_cast<double>(r.model.size()));
  ctx.record("initial_gaussians", static_cast<double>(r.initial_gaussians));
  if (o.floaters.active())
    ctx.record("free_space_pruned", static_cast<double>(r.free_space_pruned));
  ctx.record("model_bytes",
             static_cast<double>(sizeof(float) *
                                 (r.model.means.size() + r.model.log_scales.size() +
                                  r.model.quats.size() + r.model.sh.size() +
                                  r.model.opacity_logits.size() + r.model.features.size())));
  ctx.record("iterations_run", r.iterations_run);
  ctx.record("stopped_early", r.stopped_early ? "true" : "false");
  ctx.record("size_reason", model_size_reason(r));
  ctx.record("growth_refused", static_cast<double>(r.growth_refused));
  ctx.record("depth_prior_views", static_cast<double>(r.depth_prior_views));
  ctx.record("seconds", r.seconds);
  if (o.poses.refine) record_pose_changes(ctx, *ctx.input<Capture>("capture"), r.poses);
  // Where the time went (wall seconds per phase): what a user trading a lever's gain against its
  // cost reads first.
  ctx.record("prepare_seconds", r.phases.prepare);
  ctx.record("render_seconds", r.phases.render);
  ctx.record("losses_seconds", r.phases.losses);
  ctx.record("backward_seconds", r.phases.backward);
  ctx.record("adam_seconds", r.phases.adam);
  ctx.record("density_seconds", r.phases.density);
  if (o.poses.refine) ctx.record("held_out_poses_seconds", r.phases.held_out_poses);
  for (const auto& [term, seconds] : r.phases.terms) ctx.record("term_seconds/" + term, seconds);
  ctx.record("scene_extent", r.scene_extent);
  record_losses_and_geometry(ctx, r);
  const auto dir = ctx.out_dir();
  if (!dir.empty()) {
    write_ply(r.model, dir / "model.ply");
    if (o.poses.refine)
      write_file_atomically(dir / "refined_poses.txt",
                            view_poses_text(view_poses(*ctx.input<Capture>("capture"), r.poses)));
    const Capture& capture = *ctx.input<Capture>("capture");
    const std::vector<int> test = capture.test_views();
    for (size_t k = 0; k < r.test_pictures.size() && k < test.size(); ++k)
      write_rgb_png(dir / (capture.views[test[k]].name + "_heldout_geometry.png"),
                    with_caption(r.test_pictures[k],
                                 capture.views[test[k]].name +
                                     " (held out): the render against ground-truth depth",
                                 view_geometry_legend()));
  }
  // Recorded and written above first, so that run.json and model.ply show the failure.
  const std::string failure = reconstruction_failure(r, p.min_train_psnr);
  if (!failure.empty()) throw InputError(failure);
  ctx.output("model", std::move(r.model));
  ctx.output("poses", view_poses(*ctx.input<Capture>("capture"), r.poses));
}

void add_reconstruct(Registry& registry) {
  NodeSpec spec{
      "splat.reconstruct",
      "geometry-constrained 3DGS reconstruction of the capture's training views (LangOR 3.2)",
      {capture_port({{CaptureItem::Images}})},
      {model_port("the trained Gaussians; also written as model.ply (INRIA layout), and with "
                  "ground-truth depth <view>_heldout_geometry.png per held-out view (floaters "
                  "red, holes blue, surfaces no training view saw grey)"),
       {"poses", PortTypeName<ViewPoses>::value,
        "every view's pose: refined with refine_poses, else as written (splat.refined_capture "
        "puts them into the capture)"}}};
  registry.add(std::move(spec), reconstruct_node_param_table(), run_reconstruct);
}

struct RefinedCaptureOptions {};

void run_refined_capture(NodeContext& ctx, const RefinedCaptureOptions&) {
  Capture capture = *ctx.input<Capture>("capture");
  apply_view_poses(capture, *ctx.input<ViewPoses>("poses"), "splat.refined_capture: port 'poses'");
  ctx.output("capture", std::move(capture));
}

// The capture with the poses the reconstruction refined, for the stages after it that render at
// the capture's views: they then see each view where its photo is.
void add_refined_capture(Registry& registry) {
  NodeSpec spec{"splat.refined_capture",
                "the capture with the poses splat.reconstruct refined (its port `poses`)",
                {capture_port({}),
                 {"poses", PortTypeName<ViewPoses>::value, "a pose per view of the capture"}},
                {{"capture", PortTypeName<Capture>::value, "the capture, its poses replaced"}}};
  registry.add(std::move(spec), ParamTable<RefinedCaptureOptions>(), run_refined_capture);
}

// splat.load's one param.
struct LoadOptions {
  std::string path;
};

void run_load(NodeContext& ctx, const LoadOptions& o) {
  GaussianModel model = read_ply(o.path);
  ctx.record("gaussians", static_cast<double>(model.size()));
  ctx.record("feature_dim", model.feature_dim);
  ctx.output("model", std::move(model));
}

// A model saved by an earlier run (recon/model.ply) or by the reference 3DGS code, so that the
// stages after reconstruction can be rerun or swapped without training again.
void add_load(Registry& registry) {
  NodeSpec spec{"splat.load",
                "reads a Gaussian model from an INRIA-layout PLY (e.g. an earlier run's "
                "recon/model.ply)",
                {},
                {model_port("the Gaussians of the file, features and ids included")}};
  registry.add(std::move(spec),
               ParamTable<LoadOptions>().add("path", &LoadOptions::path, "the PLY file").required(),
               run_load);
}

// splat.render's params.
struct RenderNodeOptions {
  std::vector<std::string> channels{"rgb"};  // of image_channels()
  ViewSet views = ViewSet::Test;
};

void run_render(NodeContext& ctx, const RenderNodeOptions& o) {
  const auto model = ctx.input<GaussianModel>("model");
  const auto capture = ctx.input<Capture>("capture");
  RenderSettings settings;
  settings.rgb = false;
  for (const auto& c : o.channels) request_channel(settings, c);
  settings.normalize_depth = true;  // a picture of the surface, not of the blend weights
  const auto dir = ctx.out_dir();
  const std::vector<int> views = capture->views_named(o.views);
  // Every camera before the first render: a view too large to render (kMaxImagePixels) is bad
  // input naming the view, not hours of work followed by an out-of-memory kill.
  for (int v : views)
    check_camera(capture->views[v].camera, "view '" + capture->views[v].name + "'");
  for (size_t k = 0; k < views.size(); ++k) {
    ctx.check_cancelled();
    const View& view = capture->views[views[k]];
    const RenderOutput out = render(*model, view.camera, view.pose, settings);
    for (const auto& c : o.channels) {
      if (!dir.empty())
        write_rgb_png(
            dir / (view.name + "_" + c + ".png"),
            with_caption(channel_image(out, c), view.name + " " + c + ": " + channel_meaning(c)));
    }
    ctx.progress(static_cast<double>(k + 1) / views.size(), view.name);
  }
  ctx.record("views_rendered", static_cast<double>(views.size()));
}

void add_render(Registry& registry) {
  using O = RenderNodeOptions;
  NodeSpec spec{"splat.render",
                "renders channels of a Gaussian model at the capture's views and writes PNGs",
                {model_port("the Gaussians to render"),
                 capture_port({{CaptureItem::HeldOutViews, "views", "test"}})},
                {}};
  registry.add(
      std::move(spec),
      ParamTable<O>()
          .add("channels", &O::channels,
               "channels to write, each as <view>_<channel>.png: rgb, depth, normal, alpha, "
               "features",
               image_channels())
          .add("views", &O::views, view_set_names(), "which views to render"),
      run_render);
}

}  // namespace

void register_splat_nodes(Registry& registry) {
  add_reconstruct(registry);
  add_refined_capture(registry);
  add_load(registry);
  add_render(registry);
}

}  // namespace gslift
