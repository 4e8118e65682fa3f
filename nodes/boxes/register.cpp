#include "nodes/boxes/register.hpp"

#include "nodes/boxes/box_masks.hpp"
#include "nodes/boxes/cluster_boxes.hpp"
#include "nodes/boxes/grabcut_priors.hpp"
#include "nodes/scene/context_prompt.hpp"

namespace gslift {
namespace {

void run_cluster(NodeContext& ctx, const BoxClusteringParams& p) {
  BoxSet clusters = cluster_box_set(*ctx.input<BoxSet>("boxes"), p);
  size_t count = 0;
  for (const auto& v : clusters.views) count += v.boxes.size();
  ctx.record("clusters", static_cast<double>(count));
  ctx.output("clusters", std::move(clusters));
}

void add_cluster(Registry& registry) {
  NodeSpec spec{
      "boxes.cluster",
      "multi-round VLM boxes -> one box per object per view (LangOR Eq. 2, label vote)",
      {{"boxes", "BoxSet", "candidate boxes of every view, all rounds together"}},
      {{"clusters", "BoxSet", "one representative per cluster, with support and label vote"}}};
  registry.add(std::move(spec), box_clustering_param_table(), run_cluster);
}

// boxes.prompt's one param: the vocabulary file. Like every path param, a relative value written
// in a graph file is relative to that file; the default is written in none, so it is relative to
// the current directory (the repository root): a graph meant to run from anywhere sets it.
struct PromptParams {
  std::string vocabulary = "graphs/vocabulary/or.yaml";
};

const ParamTable<PromptParams>& prompt_param_table() {
  static const ParamTable<PromptParams> table =
      ParamTable<PromptParams>()
          .add("vocabulary", &PromptParams::vocabulary,
               "vocabulary file: classes with spatial, behaviour, appearance context")
          .path();
  return table;
}

void run_prompt(NodeContext& ctx, const PromptParams& p) {
  Vocabulary vocabulary = load_vocabulary(p.vocabulary);
  ctx.record("classes", static_cast<double>(vocabulary.entities.size()));
  ctx.output("prompt", std::move(vocabulary));
}

void add_prompt(Registry& registry) {
  NodeSpec spec{"boxes.prompt",
                "OR vocabulary YAML -> context-aware grounding prompt for the VLM (LangOR §1.1)",
                {},
                {{"prompt", "Vocabulary", "the vocabulary with its prompt text"}}};
  registry.add(std::move(spec), prompt_param_table(), run_prompt);
}

void run_to_masks(NodeContext& ctx, const BoxMaskOptions& o) {
  const MaskSet none;
  const MaskSet& sam = ctx.has_input("sam") ? *ctx.input<MaskSet>("sam") : none;
  BoxMaskResult r =
      box_masks(*ctx.input<BoxSet>("clusters"), *ctx.input<Capture>("capture"), sam, o);
  ctx.record("from_sam", r.from_sam);
  ctx.record("from_grabcut", r.from_grabcut);
  ctx.record("from_box", r.from_box);
  if (o.duplicates.repair != DuplicateRepair::Keep) {  // keep looks for none
    ctx.record("duplicates", r.duplicates.duplicates);
    ctx.record("regrown", r.duplicates.regrown);
    ctx.record("dropped", r.duplicates.dropped);
  }
  ctx.output("masks", std::move(r.masks));
}

void add_to_masks(Registry& registry) {
  NodeSpec spec{
      "boxes.to_masks",
      "clustered boxes -> one instance mask each: SAM box-prompt masks, GrabCut fallback",
      {{"clusters", "BoxSet", "representative boxes of every view (boxes.cluster)"},
       {"capture", "Capture", "views with RGB and optional depth prior (for GrabCut)"},
       {"sam", "MaskSet",
        "SAM masks prompted with these clusters' boxes, linked by box_index (ingest.sam_masks, "
        "kind box, boxes = the clusters); unwired = none, so sam fails and auto is GrabCut",
        true}},
      {{"masks", "MaskSet", "one mask per clustered box, label and box_index of its box"}}};
  registry.add(std::move(spec), box_mask_param_table(), run_to_masks);
}

void run_grabcut_priors(NodeContext& ctx, const GrabcutPriorOptions& o) {
  const MaskSet none;
  const MaskSet& masks = ctx.has_input("masks") ? *ctx.input<MaskSet>("masks") : none;
  DetectorPriorMaps r =
      detector_prior_maps(*ctx.input<Capture>("capture"), *ctx.input<BoxSet>("boxes"), masks, o);
  ctx.record("painted", r.painted);
  ctx.record("refined", r.refined);
  ctx.record("unknown_labels", r.unknown_labels);
  ctx.output("priors", std::move(r.priors));
}

void add_grabcut_priors(Registry& registry) {
  NodeSpec spec{
      "boxes.grabcut_priors",
      "detections -> per-pixel class and confidence per view: priors refined by GrabCut on RGB "
      "and depth, painted largest first (paper 002 Algorithm 1)",
      {{"capture",
        "Capture",
        "views with RGB, depth prior and the class vocabulary",
        false,
        {{CaptureItem::GtClasses, "classes", "[]"}}},
       {"boxes", "BoxSet", "detections per view (boxes.cluster), label and score each"},
       {"masks", "MaskSet",
        "a mask per box linked by box_index (boxes.to_masks); unwired: box priors only", true}},
      {{"priors", "SemanticMaps", "per view: the painting prior's class with its score"}}};
  registry.add(std::move(spec), grabcut_prior_param_table(), run_grabcut_priors);
}

}  // namespace

void register_boxes_nodes(Registry& registry) {
  add_cluster(registry);
  add_prompt(registry);
  add_to_masks(registry);
  add_grabcut_priors(registry);
}

}  // namespace gslift
