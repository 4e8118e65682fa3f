#include "nodes/boxes/register.hpp"

#include "nodes/boxes/box_masks.hpp"
#include "nodes/boxes/cluster_boxes.hpp"
#include "nodes/boxes/context_prompt.hpp"

namespace gslift {
namespace {

void add_cluster(Registry& registry) {
  const BoxClusteringParams d;
  NodeSpec spec{
      "boxes.cluster",
      "multi-round VLM boxes -> one box per object per view (LangOR Eq. 2, label vote)",
      {{"boxes", "BoxSet", "candidate boxes of every view, all rounds together"}},
      {{"clusters", "BoxSet", "one representative per cluster, with support and label vote"}},
      {float_param("iou", d.iou,
                   "boxes with the seed's label join its cluster when their IoU with it exceeds "
                   "this",
                   0, 1),
       float_param("any_label_iou", d.any_label_iou,
                   "boxes with another label join only above this IoU (1 = never; = iou: "
                   "label-blind, as in the paper)",
                   0, 1),
       int_param("min_support", d.min_support,
                 "drop clusters seen in fewer distinct rounds (clamped to the rounds asked)", 1)}};
  registry.add(std::move(spec), [](NodeContext& ctx) {
    BoxClusteringParams p;
    p.iou = ctx.param_float("iou");
    p.any_label_iou = ctx.param_float("any_label_iou");
    p.min_support = static_cast<int>(ctx.param_int("min_support"));
    BoxSet clusters = cluster_box_set(*ctx.input<BoxSet>("boxes"), p);
    size_t count = 0;
    for (const auto& v : clusters.views) count += v.boxes.size();
    ctx.record("clusters", static_cast<double>(count));
    ctx.output("clusters", std::move(clusters));
  });
}

void add_prompt(Registry& registry) {
  NodeSpec spec{"boxes.prompt",
                "OR vocabulary YAML -> context-aware grounding prompt for the VLM (LangOR §1.1)",
                {},
                {{"prompt", "Vocabulary", "the vocabulary with its prompt text"}},
                {string_param("vocabulary", "graphs/vocabulary/or.yaml",
                              "vocabulary file: classes with spatial, behaviour, appearance "
                              "context")}};
  registry.add(std::move(spec), [](NodeContext& ctx) {
    Vocabulary vocabulary = load_vocabulary(ctx.param_string("vocabulary"));
    ctx.record("classes", static_cast<double>(vocabulary.entities.size()));
    ctx.output("prompt", std::move(vocabulary));
  });
}

void add_to_masks(Registry& registry) {
  const BoxMaskOptions d;
  NodeSpec spec{
      "boxes.to_masks",
      "clustered boxes -> one instance mask each: SAM box-prompt masks, GrabCut fallback",
      {{"clusters", "BoxSet", "representative boxes of every view (boxes.cluster)"},
       {"capture", "Capture", "views with RGB, optional depth prior and SAM box masks"}},
      {{"masks", "MaskSet", "one mask per clustered box, label and box_index of its box"}},
      {string_param("source", d.source,
                    "sam: the capture's SAM mask of the box (missing = bad input); grabcut: "
                    "GrabCut on RGB and depth; auto: sam where present, else grabcut",
                    {"sam", "grabcut", "auto"}),
       int_param("grabcut_iterations", d.grabcut_iterations, "GrabCut iterations (paper: 5)", 1,
                 100),
       float_param("context", d.context,
                   "GrabCut crop: the box grown by this fraction of its size on each side", 0, 10),
       bool_param("use_depth", d.use_depth, "also run GrabCut on the depth prior, OR-ed")}};
  registry.add(std::move(spec), [](NodeContext& ctx) {
    BoxMaskOptions o;
    o.source = ctx.param_string("source");
    o.grabcut_iterations = static_cast<int>(ctx.param_int("grabcut_iterations"));
    o.context = static_cast<float>(ctx.param_float("context"));
    o.use_depth = ctx.param_bool("use_depth");
    BoxMaskResult r = box_masks(*ctx.input<BoxSet>("clusters"), *ctx.input<Capture>("capture"), o);
    ctx.record("from_sam", r.from_sam);
    ctx.record("from_grabcut", r.from_grabcut);
    ctx.record("from_box", r.from_box);
    ctx.output("masks", std::move(r.masks));
  });
}

}  // namespace

void register_boxes_nodes(Registry& registry) {
  add_cluster(registry);
  add_prompt(registry);
  add_to_masks(registry);
}

}  // namespace gslift
