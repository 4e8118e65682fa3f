#include "nodes/splat/register.hpp"

#include <cmath>

#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/image_io.hpp"
#include "nodes/splat/channel_images.hpp"
#include "nodes/splat/ply_io.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "nodes/splat/reconstruct.hpp"

namespace gslift {
namespace {

PortSpec capture_port() {
  return {"capture", PortTypeName<Capture>::value, "posed views with an optional depth prior"};
}

PortSpec model_port(const std::string& doc) {
  return {"model", PortTypeName<GaussianModel>::value, doc};
}

void add_reconstruct(Registry& registry) {
  const ReconstructOptions d;
  NodeSpec spec{
      "splat.reconstruct",
      "geometry-constrained 3DGS reconstruction of the capture's training views (LangOR 3.2)",
      {capture_port()},
      {model_port("the trained Gaussians; also written as model.ply (INRIA layout)")},
      {int_param("iterations", d.iterations, "optimisation steps (LangOR: 500)", 1, 1e6),
       int_param("sh_degree", d.sh_degree, "highest SH degree, raised one every 100 steps", 0, 3),
       float_param("ssim_lambda", d.ssim_lambda, "weight of D-SSIM in the photometric loss", 0, 1),
       float_param("depth_weight", d.depth_weight,
                   "depth log-L1 against the depth prior (DN-Splatter 0.2); 0 = off", 0),
       float_param("normal_weight", d.normal_weight,
                   "1 - cos between rendered normals and depth-prior normals; 0 = off", 0),
       float_param("scale_weight", d.scale_weight,
                   "flatness regulariser, mean smallest scale in metres; 0 = off", 0),
       float_param("coarse_fraction", d.coarse_fraction,
                   "fraction of the steps trained at half resolution first; 0 = off", 0, 1),
       bool_param("densify", d.densify, "clone/split/prune on the compressed schedule"),
       int_param("max_gaussians", static_cast<int64_t>(d.density.max_gaussians),
                 "Gaussian budget for densification", 1),
       int_param("feature_dim", d.feature_dim,
                 "feature channels allocated (zero) for later stages, not trained here", 0, 512),
       string_param("init", d.init.source,
                    "initial points: depth prior, sparse points, or auto (depth when every "
                    "training view has one)",
                    {"auto", "depth", "points"}),
       float_param("footprint_factor", d.init.footprint_factor,
                   "initial voxel = this x the median pixel footprint (larger = fewer Gaussians)",
                   0.1, 100),
       float_param("normal_thickness", d.init.normal_thickness,
                   "initial scale along the depth prior's normal / in-plane scale (1 = isotropic)",
                   0.01, 1),
       int_param("plateau_window", d.plateau_window,
                 "early stop when a window of this many steps improves the mean loss by less "
                 "than plateau_tolerance; 0 = off",
                 0),
       float_param("plateau_tolerance", d.plateau_tolerance,
                   "relative improvement per window below which the run stops", 0, 1)}};
  registry.add(std::move(spec), [](NodeContext& ctx) {
    const auto capture = ctx.input<Capture>("capture");
    ReconstructOptions o;
    o.iterations = static_cast<int>(ctx.param_int("iterations"));
    o.sh_degree = static_cast<int>(ctx.param_int("sh_degree"));
    o.ssim_lambda = ctx.param_float("ssim_lambda");
    o.depth_weight = ctx.param_float("depth_weight");
    o.normal_weight = ctx.param_float("normal_weight");
    o.scale_weight = ctx.param_float("scale_weight");
    o.coarse_fraction = ctx.param_float("coarse_fraction");
    o.densify = ctx.param_bool("densify");
    o.density.max_gaussians = static_cast<size_t>(ctx.param_int("max_gaussians"));
    o.feature_dim = static_cast<int>(ctx.param_int("feature_dim"));
    o.init.source = ctx.param_string("init");
    o.init.footprint_factor = ctx.param_float("footprint_factor");
    o.init.normal_thickness = ctx.param_float("normal_thickness");
    o.plateau_window = static_cast<int>(ctx.param_int("plateau_window"));
    o.plateau_tolerance = ctx.param_float("plateau_tolerance");
    o.seed = ctx.seed();
    ReconstructResult r = reconstruct(*capture, o, [&](int step, int total, double, size_t) {
      ctx.check_cancelled();
      ctx.progress(static_cast<double>(step + 1) / total, "optimising");
    });
    ctx.record("gaussians", static_cast<double>(r.model.size()));
    ctx.record("initial_gaussians", static_cast<double>(r.initial_gaussians));
    ctx.record("model_bytes",
               static_cast<double>(sizeof(float) *
                                   (r.model.means.size() + r.model.log_scales.size() +
                                    r.model.quats.size() + r.model.sh.size() +
                                    r.model.opacity_logits.size() + r.model.features.size())));
    ctx.record("iterations_run", r.iterations_run);
    ctx.record("stopped_early", r.stopped_early ? "true" : "false");
    ctx.record("seconds", r.seconds);
    ctx.record("scene_extent", r.scene_extent);
    ctx.record("loss_total", r.final_loss.total);
    ctx.record("loss_photometric", r.final_loss.photometric);
    ctx.record("loss_depth", r.final_loss.depth);
    ctx.record("loss_normal", r.final_loss.normal);
    ctx.record("loss_flatness", r.final_loss.flatness);
    ctx.record("train_psnr", r.train_psnr);
    if (!std::isnan(r.test_psnr)) ctx.record("test_psnr", r.test_psnr);
    if (r.test_geometry) {
      // NaN (no such pixel) is left out: run.json holds numbers only.
      const ViewGeometry& g = *r.test_geometry;
      const std::pair<const char*, double> geometry[] = {
          {"test_psnr_covered", g.psnr_covered},
          {"test_coverage", g.coverage},
          {"test_depth_abs_rel_median", g.depth_abs_rel_median},
          {"test_depth_within_5pct", g.depth_within_5pct},
          {"test_floaters", g.floaters},
          {"test_holes", g.holes},
          {"test_holes_covered", g.holes_covered}};
      for (const auto& [key, value] : geometry)
        if (std::isfinite(value)) ctx.record(key, value);
    }
    const auto dir = ctx.out_dir();
    if (!dir.empty()) write_ply(r.model, dir / "model.ply");
    ctx.output("model", std::move(r.model));
  });
}

// A model saved by an earlier run (recon/model.ply) or by the reference 3DGS code, so that the
// stages after reconstruction can be rerun or swapped without training again.
void add_load(Registry& registry) {
  NodeSpec spec{"splat.load",
                "reads a Gaussian model from an INRIA-layout PLY (e.g. an earlier run's "
                "recon/model.ply)",
                {},
                {model_port("the Gaussians of the file, features and ids included")},
                {required_string_param("path", "the PLY file")}};
  registry.add(std::move(spec), [](NodeContext& ctx) {
    GaussianModel model = read_ply(ctx.param_string("path"));
    ctx.record("gaussians", static_cast<double>(model.size()));
    ctx.record("feature_dim", model.feature_dim);
    ctx.output("model", std::move(model));
  });
}

void add_render(Registry& registry) {
  ParamSpec channels;
  channels.name = "channels";
  channels.type = ParamType::StringList;
  channels.default_value = std::vector<std::string>{"rgb"};
  channels.choices = image_channels();
  channels.doc =
      "channels to write, each as <view>_<channel>.png: rgb, depth, normal, alpha, features";
  NodeSpec spec{
      "splat.render",
      "renders channels of a Gaussian model at the capture's views and writes PNGs",
      {model_port("the Gaussians to render"), capture_port()},
      {},
      {channels, string_param("views", "test", "which views to render", {"train", "test", "all"})}};
  registry.add(std::move(spec), [](NodeContext& ctx) {
    const auto model = ctx.input<GaussianModel>("model");
    const auto capture = ctx.input<Capture>("capture");
    const auto& channels = ctx.param_strings("channels");
    RenderSettings settings;
    settings.rgb = false;
    for (const auto& c : channels) request_channel(settings, c);
    settings.normalize_depth = true;  // a picture of the surface, not of the blend weights
    const auto dir = ctx.out_dir();
    const std::vector<int> views = capture->views_named(ctx.param_string("views"));
    for (size_t k = 0; k < views.size(); ++k) {
      ctx.check_cancelled();
      const View& view = capture->views[views[k]];
      const RenderOutput out = render(*model, view.camera, view.pose, settings);
      for (const auto& c : channels) {
        if (!dir.empty())
          write_rgb_png(dir / (view.name + "_" + c + ".png"), channel_image(out, c));
      }
      ctx.progress(static_cast<double>(k + 1) / views.size(), view.name);
    }
    ctx.record("views_rendered", static_cast<double>(views.size()));
  });
}

}  // namespace

void register_splat_nodes(Registry& registry) {
  add_reconstruct(registry);
  add_load(registry);
  add_render(registry);
}

}  // namespace gslift
