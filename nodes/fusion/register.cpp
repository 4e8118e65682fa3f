#include "nodes/fusion/register.hpp"

#include <atomic>

#include <tbb/parallel_for.h>

#include "base/errors.hpp"
#include "nodes/fusion/bayesian_fusion.hpp"
#include "nodes/fusion/cluster_smoothing.hpp"
#include "nodes/fusion/multiview_fusion.hpp"
#include "nodes/fusion/render_semantics.hpp"
#include "nodes/fusion/supervoxels.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/instances.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "nodes/splat/render_cache.hpp"

namespace gslift {
namespace {

// The capture view each semantic view names; throws InputError when one is missing.
const View& view_of(const Capture& capture, const SemanticView& sv, const char* node) {
  const int v = capture.find_view(sv.view);
  if (v < 0)
    throw InputError(std::string(node) + ": semantics name view '" + sv.view +
                     "' that the capture '" + capture.name + "' lacks");
  return capture.views[v];
}

// The depth the 3D stages work on: the capture's depth prior (the paper's RGB-D sensor).
cv::Mat1f view_depth(const View& view, const char* node) {
  const cv::Mat depth = view.depth.load();
  if (depth.empty())
    throw InputError(std::string(node) + ": view '" + view.name +
                     "' has no depth prior (multi-view fusion and cluster smoothing back-project "
                     "it)");
  return depth;
}

void run_render_semantics(NodeContext& ctx, const RenderSemanticsOptions& o) {
  const auto model = ctx.input<GaussianModel>("model");
  const auto instances = ctx.input<InstanceSet>("instances");
  const auto capture = ctx.input<Capture>("capture");
  if (model->instance_ids.size() != model->size())
    throw InputError("fusion.render_semantics: the model has " +
                     std::to_string(model->instance_ids.size()) + " instance ids for " +
                     std::to_string(model->size()) +
                     " Gaussians (segment it first, e.g. association.instance_mask_gaussian)");
  SemanticMaps out;
  out.classes = semantic_classes(*capture);
  const int classes = out.class_count();
  std::vector<int> instance_class;
  int unknown = 0;
  for (const std::string& label : instances->labels) {
    instance_class.push_back(class_index(out.classes, label));
    if (instance_class.back() < 0) ++unknown;
  }
  const std::vector<float> per_gaussian =
      gaussian_class_probabilities(model->instance_ids, instance_class, classes, o);
  const std::vector<float> background = background_distribution(classes, o);
  out.views.resize(capture->views.size());
  // One view at a time: a render cache holds millions of (pixel, Gaussian) pairs.
  for (size_t v = 0; v < capture->views.size(); ++v) {
    const View& view = capture->views[v];
    RenderSettings settings;
    settings.rgb = false;  // only the blend weights
    const RenderCache cache(render(*model, view.camera, view.pose, settings));
    out.views[v] = semantics_from_blend(view.name, cache.render(per_gaussian, classes), background,
                                        classes, view.camera.width, view.camera.height);
  }
  ctx.record("classes", classes);
  ctx.record("unknown_labels", unknown);
  ctx.output("semantics", std::move(out));
}

void run_bayesian(NodeContext& ctx) {
  const auto a = ctx.input<SemanticMaps>("bottom_up");
  const auto b = ctx.input<SemanticMaps>("top_down");
  if (a->classes != b->classes || a->views.size() != b->views.size())
    throw InputError("fusion.bayesian: the two sources differ in classes (" +
                     std::to_string(a->class_count()) + " and " + std::to_string(b->class_count()) +
                     ") or views (" + std::to_string(a->views.size()) + " and " +
                     std::to_string(b->views.size()) + ")");
  SemanticMaps out;
  out.classes = a->classes;
  out.views.resize(a->views.size());
  std::atomic<long long> changed{0};
  tbb::parallel_for(size_t(0), a->views.size(), [&](size_t v) {
    const SemanticView& x = a->views[v];
    if (b->views[v].view != x.view)
      throw InputError("fusion.bayesian: view " + std::to_string(v) + " is '" + x.view +
                       "' in one source and '" + b->views[v].view + "' in the other");
    out.views[v] = fuse_bayesian(x, b->views[v], out.class_count(), x.labels.cols, x.labels.rows);
    changed += cv::countNonZero(out.views[v].labels != x.labels);
  });
  ctx.record("changed_from_bottom_up", static_cast<double>(changed));
  ctx.output("semantics", std::move(out));
}

void run_multiview(NodeContext& ctx, const MultiviewFusionOptions& o) {
  const auto in = ctx.input<SemanticMaps>("semantics");
  const auto capture = ctx.input<Capture>("capture");
  std::vector<FusionFrame> frames(in->views.size());
  for (size_t v = 0; v < frames.size(); ++v) {
    const View& view = view_of(*capture, in->views[v], "fusion.multiview");
    frames[v] = {view.camera, view.pose, view_depth(view, "fusion.multiview"), &in->views[v]};
  }
  SemanticMaps out;
  out.classes = in->classes;
  out.views.resize(frames.size());
  std::atomic<long long> contributions{0}, changed{0};
  // Every view is the reference in turn (paper 002 §3.2), in parallel.
  tbb::parallel_for(size_t(0), frames.size(), [&](size_t v) {
    MultiviewFusionResult r = fuse_multiview(frames, static_cast<int>(v), in->class_count(), o);
    contributions += r.contributions;
    changed += r.changed;
    out.views[v] = std::move(r.fused);
  });
  ctx.record("contributions", static_cast<double>(contributions));
  ctx.record("changed", static_cast<double>(changed));
  ctx.output("semantics", std::move(out));
}

void run_cluster_smoothing(NodeContext& ctx, const SupervoxelOptions& o) {
  const auto in = ctx.input<SemanticMaps>("semantics");
  const auto capture = ctx.input<Capture>("capture");
  SemanticMaps out;
  out.classes = in->classes;
  out.views.resize(in->views.size());
  std::atomic<long long> clusters{0}, changed{0};
  tbb::parallel_for(size_t(0), in->views.size(), [&](size_t v) {
    const View& view = view_of(*capture, in->views[v], "fusion.cluster_smoothing");
    const cv::Mat rgb = view.rgb.load();
    if (rgb.empty())
      throw InputError("fusion.cluster_smoothing: view '" + view.name + "' has no RGB image");
    const cv::Mat1i segments =
        oversegment_rgbd(rgb, view_depth(view, "fusion.cluster_smoothing"), view.camera, o);
    ClusterSmoothingResult r = smooth_clusters(in->views[v], segments, in->class_count());
    clusters += r.clusters;
    changed += r.changed;
    out.views[v] = std::move(r.smoothed);
  });
  ctx.record("clusters", static_cast<double>(clusters));
  ctx.record("changed", static_cast<double>(changed));
  ctx.output("semantics", std::move(out));
}

const char* kSemantics = PortTypeName<SemanticMaps>::value;

}  // namespace

void register_fusion_nodes(Registry& registry) {
  registry.add(
      {"fusion.render_semantics",
       "segmented Gaussians -> per-pixel class distribution in every view (render cache, the "
       "bottom-up source of paper 002)",
       {{"model", PortTypeName<GaussianModel>::value, "Gaussians with instance_ids"},
        {"instances", PortTypeName<InstanceSet>::value, "instance labels (class names)"},
        {"capture", PortTypeName<Capture>::value, "views and the class vocabulary"}},
       {{"semantics", kSemantics, "rendered class distributions, every capture view"}}},
      render_semantics_param_table(), run_render_semantics);
  registry.add({"fusion.bayesian",
                "per-pixel Bayesian fusion of two class distributions, argmax label (paper 002 "
                "Algorithm 2)",
                {{"bottom_up", kSemantics, "the 3D source (fusion.render_semantics)"},
                 {"top_down", kSemantics, "the detector priors (boxes.grabcut_priors)"}},
                {{"semantics", kSemantics, "fused distributions and labels"}}},
               run_bayesian);
  registry.add({"fusion.multiview",
                "multi-view frame fusion with depth validation and Moore-neighbourhood votes, "
                "every view the reference in turn (paper 002 §3.2, Eq. 1)",
                {{"semantics", kSemantics, "per-view distributions and labels"},
                 {"capture", PortTypeName<Capture>::value, "posed views with depth priors"}},
                {{"semantics", kSemantics, "fused per view"}}},
               multiview_fusion_param_table(), run_multiview);
  registry.add({"fusion.cluster_smoothing",
                "majority label and confidences over each supervoxel of the view's back-projected "
                "depth (paper 002 Algorithm 2 line 5)",
                {{"semantics", kSemantics, "per-view distributions and labels"},
                 {"capture", PortTypeName<Capture>::value, "views with RGB and depth priors"}},
                {{"semantics", kSemantics, "smoothed per view"}}},
               supervoxel_param_table(), run_cluster_smoothing);
}

}  // namespace gslift
