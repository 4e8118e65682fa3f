#include "nodes/eval/register.hpp"

#include <cstdio>

#include "nodes/eval/binary_segmentation.hpp"
#include "nodes/eval/langor_eval.hpp"
#include "runtime/atomic_file.hpp"

namespace gslift {

namespace {

void run_langor_eval(NodeContext& ctx, const LangorEvalOptions& o) {
  const LangorSummary s = summarise_langor(
      score_langor(*ctx.input<TextQueryResults>("predictions"), *ctx.input<Capture>("capture"), o));
  ctx.record("queries", static_cast<double>(s.queries));
  ctx.record("classes", static_cast<double>(s.classes.size()));
  ctx.record("mIoU", s.miou);
  ctx.record("mIoU_class", s.miou_class);
  ctx.record("mLocAcc", s.mlocacc);
  ctx.record("mLocAcc_box", s.mlocacc_box);
  ctx.record("mAcc", s.macc);
  for (const auto& c : s.classes) ctx.record("IoU/" + c.label, c.iou);
  const std::string markdown = langor_table_markdown(s);
  const auto dir = ctx.out_dir();
  if (!dir.empty()) {
    write_file_atomically(dir / "metrics.csv", langor_table_csv(s));
    write_file_atomically(dir / "metrics.md", markdown);
    // The metrics table, printed at the end of the main job.
    std::fputs(("\n" + markdown).c_str(), stdout);
  }
}

void run_binary_segmentation(NodeContext& ctx, const BinarySegmentationOptions& o) {
  const BinarySegmentationSummary s = score_binary_segmentation(*ctx.input<MaskSet>("predictions"),
                                                                *ctx.input<MaskSet>("truth"), o);
  ctx.record("prompts", static_cast<double>(s.labels.size()));
  ctx.record("target_views", static_cast<double>(s.views.size()));
  ctx.record("mIoU", s.miou);
  ctx.record("mAcc", s.macc);
  for (const auto& l : s.labels) ctx.record("IoU/" + l.label, l.iou);
  const std::string markdown = binary_segmentation_markdown(s);
  const auto dir = ctx.out_dir();
  if (!dir.empty()) {
    write_file_atomically(dir / "metrics.csv", binary_segmentation_csv(s));
    write_file_atomically(dir / "metrics.md", markdown);
    std::fputs(("\n" + markdown).c_str(), stdout);
  }
}

}  // namespace

void register_eval_nodes(Registry& registry) {
  registry.add(NodeSpec{"eval.binary_segmentation",
                        "IoU = TP / (TP + FP + FN) and accuracy of prompted masks per target view, "
                        "averaged (NVOS / SPIn-NeRF, as SAGA reports them)",
                        {{"predictions", PortTypeName<MaskSet>::value,
                          "per view one mask per prompt (inference.render_selection)"},
                         {"truth", PortTypeName<MaskSet>::value,
                          "ground-truth masks with the prompts' labels (masks.ground_truth)"}},
                        {}},
               binary_segmentation_param_table(), run_binary_segmentation);
  NodeSpec spec{
      "eval.langor",
      "mIoU, mLocAcc and mAcc of text queries on the held-out views (LangOR 4.1, LangSplat)",
      {{"predictions", PortTypeName<TextQueryResults>::value,
        "masks and relevancy maps of the class-name queries (inference.text_query)"},
       {"capture", PortTypeName<Capture>::value, "held-out views with ground-truth semantics"}},
      {}};
  registry.add(std::move(spec), langor_eval_param_table(), run_langor_eval);
}

}  // namespace gslift
