#include "nodes/boxes/register.hpp"

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
      {float_param("iou", d.iou, "boxes join a cluster when their IoU with its seed exceeds this",
                   0, 1),
       int_param("min_support", d.min_support,
                 "drop clusters seen in fewer distinct rounds (clamped to the rounds asked)", 1)}};
  registry.add(std::move(spec), [](NodeContext& ctx) {
    BoxClusteringParams p;
    p.iou = static_cast<float>(ctx.param_float("iou"));
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

}  // namespace

void register_boxes_nodes(Registry& registry) {
  add_cluster(registry);
  add_prompt(registry);
}

}  // namespace gslift
