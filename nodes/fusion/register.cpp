#include "nodes/fusion/register.hpp"

#include "base/atomic_file.hpp"
#include "nodes/fusion/bayesian_fusion.hpp"
#include "nodes/fusion/cluster_smoothing.hpp"
#include "nodes/fusion/multiview_fusion.hpp"
#include "nodes/fusion/render_semantics.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/instances.hpp"
#include "nodes/scene/label_maps.hpp"

namespace gslift {
namespace {

void run_render_semantics(NodeContext& ctx, const RenderSemanticsOptions& o) {
  int unknown = 0;
  SemanticMaps out = render_semantic_maps(*ctx.input<GaussianModel>("model"),
                                          ctx.input<InstanceSet>("instances")->labels,
                                          *ctx.input<Capture>("capture"), o, &unknown);
  ctx.record("classes", out.class_count());
  ctx.record("unknown_labels", unknown);
  ctx.output("semantics", std::move(out));
}

void run_bayesian(NodeContext& ctx) {
  long long changed = 0;
  SemanticMaps out = fuse_bayesian_maps(*ctx.input<SemanticMaps>("bottom_up"),
                                        *ctx.input<SemanticMaps>("top_down"), &changed);
  ctx.record("changed_from_bottom_up", static_cast<double>(changed));
  ctx.output("semantics", std::move(out));
}

void run_multiview(NodeContext& ctx, const MultiviewFusionOptions& o) {
  long long contributions = 0, changed = 0;
  SemanticMaps out =
      fuse_multiview_maps(*ctx.input<SemanticMaps>("semantics"), *ctx.input<Capture>("capture"), o,
                          &contributions, &changed);
  ctx.record("contributions", static_cast<double>(contributions));
  ctx.record("changed", static_cast<double>(changed));
  ctx.output("semantics", std::move(out));
}

// The fused result as files, so that a run without ground truth has something to look at:
// <view>_labels.png (16-bit class ids, 0 also where no source said anything), <view>_overlay.png
// and classes.csv (id, name).
void write_class_map_files(const SemanticMaps& maps, const Capture& capture,
                           const std::filesystem::path& dir) {
  LabelMapSet set;
  set.labels = maps.class_count() - 1;
  for (const SemanticView& v : maps.views) {
    cv::Mat1i ids = v.labels.clone();
    ids.setTo(0, ids < 0);
    set.views.push_back({v.view, ids});
  }
  write_label_map_files(set, &capture, dir);
  std::string csv = "id,name\n";
  for (int i = 0; i < maps.class_count(); ++i)
    csv += std::to_string(i) + "," + maps.classes[i] + "\n";
  write_file_atomically(dir / "classes.csv", csv);
}

void run_cluster_smoothing(NodeContext& ctx, const SupervoxelOptions& o) {
  long long clusters = 0, changed = 0;
  const auto capture = ctx.input<Capture>("capture");
  SemanticMaps out =
      smooth_cluster_maps(*ctx.input<SemanticMaps>("semantics"), *capture, o, &clusters, &changed);
  ctx.record("clusters", static_cast<double>(clusters));
  ctx.record("changed", static_cast<double>(changed));
  const auto dir = ctx.out_dir();
  if (!dir.empty()) write_class_map_files(out, *capture, dir);
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
        {"capture",
         PortTypeName<Capture>::value,
         "views and the class vocabulary",
         false,
         {{CaptureItem::GtClasses, "classes", "[]"}}}},
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
                 {"capture",
                  PortTypeName<Capture>::value,
                  "posed views with depth priors",
                  false,
                  {{CaptureItem::Depth}}}},
                {{"semantics", kSemantics, "fused per view"}}},
               multiview_fusion_param_table(), run_multiview);
  registry.add({"fusion.cluster_smoothing",
                "majority label and confidences over each supervoxel of the view's back-projected "
                "depth (paper 002 Algorithm 2 line 5)",
                {{"semantics", kSemantics, "per-view distributions and labels"},
                 {"capture",
                  PortTypeName<Capture>::value,
                  "views with RGB and depth priors",
                  false,
                  {{CaptureItem::Depth}}}},
                {{"semantics", kSemantics,
                  "smoothed per view (files: <view>_labels.png 16-bit class ids, "
                  "<view>_overlay.png, classes.csv)"}}},
               supervoxel_param_table(), run_cluster_smoothing);
}

}  // namespace gslift
