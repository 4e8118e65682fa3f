#include "nodes/eval/register.hpp"

#include <cstdio>

#include "nodes/eval/langor_eval.hpp"
#include "runtime/atomic_file.hpp"

namespace gslift {

void register_eval_nodes(Registry& registry) {
  const LangorEvalOptions d;
  NodeSpec spec{
      "eval.langor",
      "mIoU, mLocAcc and mAcc of text queries on the held-out views (LangOR 4.1, LangSplat)",
      {{"predictions", PortTypeName<TextQueryResults>::value,
        "masks and relevancy maps of the class-name queries (inference.text_query)"},
       {"capture", PortTypeName<Capture>::value, "held-out views with ground-truth semantics"}},
      {},
      {int_param("min_gt_pixels", d.min_gt_pixels,
                 "a class is present in a view (hence queried) from this many GT pixels on", 1),
       int_param("loc_box", d.loc_box,
                 "box filter width of LangSplat's localisation variant (mLocAcc_box)", 1, 1000)}};
  registry.add(std::move(spec), [](NodeContext& ctx) {
    const auto predictions = ctx.input<TextQueryResults>("predictions");
    const auto capture = ctx.input<Capture>("capture");
    LangorEvalOptions o;
    o.min_gt_pixels = static_cast<int>(ctx.param_int("min_gt_pixels"));
    o.loc_box = static_cast<int>(ctx.param_int("loc_box"));
    const LangorSummary s = summarise_langor(score_langor(*predictions, *capture, o));
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
  });
}

}  // namespace gslift
