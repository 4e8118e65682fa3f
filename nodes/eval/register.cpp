#include "nodes/eval/register.hpp"

#include <cstdio>

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

}  // namespace

void register_eval_nodes(Registry& registry) {
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
