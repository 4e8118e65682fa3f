#include "nodes/eval/register.hpp"

#include <cstdio>

#include "nodes/eval/langor_eval.hpp"
#include "nodes/eval/semantic_eval.hpp"
#include "nodes/scene/image_io.hpp"
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

void record_scores(NodeContext& ctx, const std::string& prefix, const SemanticScores& s) {
  ctx.record(prefix + "GA", s.ga);
  ctx.record(prefix + "CA", s.ca);
  ctx.record(prefix + "CP", s.cp);
}

void run_semantic_eval(NodeContext& ctx, const SemanticEvalOptions& o) {
  const auto predictions = ctx.input<SemanticMaps>("predictions");
  const SemanticEvaluation e = evaluate_semantics(*predictions, *ctx.input<Capture>("capture"), o);
  const SemanticScores all = semantic_scores(e.all);
  record_scores(ctx, "", all);
  record_scores(ctx, "train/", semantic_scores(e.train));
  record_scores(ctx, "test/", semantic_scores(e.test));
  for (const auto& v : e.views) record_scores(ctx, "view/" + v.view + "/", v.scores);
  for (size_t i = 0; i < all.classes.size(); ++i)
    if (all.classes[i].present)
      ctx.record("recall/" + predictions->classes[i], 100 * all.classes[i].recall);
  const auto dir = ctx.out_dir();
  if (dir.empty()) return;
  write_file_atomically(dir / "classes.csv", semantic_class_csv(all, predictions->classes));
  write_file_atomically(dir / "classes_train.csv",
                        semantic_class_csv(semantic_scores(e.train), predictions->classes));
  write_file_atomically(dir / "classes_test.csv",
                        semantic_class_csv(semantic_scores(e.test), predictions->classes));
  std::string per_view = "view,held_out,GA,CA,CP\n";
  for (const auto& v : e.views)
    per_view += v.view + "," + (v.held_out ? "1" : "0") + "," + std::to_string(v.scores.ga) + "," +
                std::to_string(v.scores.ca) + "," + std::to_string(v.scores.cp) + "\n";
  write_file_atomically(dir / "views.csv", per_view);
  write_file_atomically(dir / "confusion.csv", confusion_csv(e.all, predictions->classes));
  write_rgb_png(dir / "confusion.png", confusion_heatmap(e.all));
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
  registry.add({"eval.semantic",
                "GA, CA, CP of per-pixel class maps on every view with ground truth, training and "
                "held-out views apart (paper 002 §4.2); confusion matrix CSV + PNG",
                {{"predictions", PortTypeName<SemanticMaps>::value, "per-pixel class maps"},
                 {"capture", PortTypeName<Capture>::value, "views with gt/semantic maps"}},
                {}},
               semantic_eval_param_table(), run_semantic_eval);
}

}  // namespace gslift
