#include "nodes/eval/register.hpp"

#include <spdlog/spdlog.h>

#include <cstdio>
#include <map>

#include <opencv2/imgproc.hpp>

#include "base/atomic_file.hpp"
#include "nodes/eval/binary_segmentation.hpp"
#include "nodes/eval/instance_hungarian.hpp"
#include "nodes/eval/instance_picture.hpp"
#include "nodes/eval/langor_eval.hpp"
#include "nodes/eval/mask_coverage.hpp"
#include "nodes/eval/semantic_eval.hpp"
#include "nodes/scene/caption_strip.hpp"
#include "nodes/scene/image_io.hpp"
#include "nodes/splat/channel_images.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "nodes/splat/reconstruct.hpp"

namespace gslift {

namespace {

void run_langor_eval(NodeContext& ctx, const LangorEvalOptions& o) {
  const auto& predictions = *ctx.input<TextQueryResults>("predictions");
  const auto& capture = *ctx.input<Capture>("capture");
  const LangorSummary s = summarise_langor(score_langor(predictions, capture, o));
  // With the user's queries only the classes they stand for are scored: say which were not.
  std::string unqueried;
  for (const auto& c : langor_unqueried_classes(predictions, capture))
    unqueried += (unqueried.empty() ? "" : ", ") + c;
  if (!unqueried.empty()) {
    ctx.record("classes_not_queried", unqueried);
    spdlog::warn("eval.langor: no query stands for {}: left out of the metrics", unqueried);
  }
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

struct MaskCoverageOptions {};

// Records best_iou (every granularity) and best_iou/g<k>, masks_per_view and masks_per_view/g<k>.
void run_mask_coverage(NodeContext& ctx, const MaskCoverageOptions&) {
  const std::vector<MaskCoverage> rows =
      mask_coverage(*ctx.input<MaskSet>("masks"), *ctx.input<MaskSet>("truth"));
  ctx.record("instances", static_cast<double>(rows.front().instances));
  for (const MaskCoverage& r : rows) {
    const std::string suffix = r.granularity < 0 ? "" : "/g" + std::to_string(r.granularity);
    ctx.record("best_iou" + suffix, r.mean_best_iou);
    ctx.record("masks_per_view" + suffix, r.masks_per_view);
  }
}

void run_binary_segmentation(NodeContext& ctx, const BinarySegmentationOptions& o) {
  const BinarySegmentationSummary s = score_binary_segmentation(*ctx.input<MaskSet>("predictions"),
                                                                *ctx.input<MaskSet>("truth"), o);
  ctx.record("prompts", static_cast<double>(s.labels.size()));
  ctx.record("target_views", static_cast<double>(s.views.size()));
  ctx.record("mIoU", s.miou);
  ctx.record("mAcc", s.macc);
  ctx.record("mPrecision", s.mprecision);
  ctx.record("mRecall", s.mrecall);
  for (const auto& l : s.labels) {
    ctx.record("IoU/" + l.label, l.iou);
    ctx.record("precision/" + l.label, l.precision);
    ctx.record("recall/" + l.label, l.recall);
  }
  const std::string markdown = binary_segmentation_markdown(s);
  const auto dir = ctx.out_dir();
  if (!dir.empty()) {
    write_file_atomically(dir / "metrics.csv", binary_segmentation_csv(s));
    write_file_atomically(dir / "metrics.md", markdown);
    std::fputs(("\n" + markdown).c_str(), stdout);
  }
}

// The views scored are those of the predictions; nothing to choose.
struct InstanceEvalOptions {};

// Ground truth | render | instances for each held-out view scored (the report's picture).
void write_instance_pictures(const GaussianModel& model, const Capture& capture,
                             const LabelMapSet& predictions, const InstanceScores& s,
                             const std::filesystem::path& dir) {
  std::map<int, int> pred_to_gt;
  for (size_t k = 0; k < s.gt_ids.size(); ++k)
    if (s.matched_pred[k] > 0) pred_to_gt[s.matched_pred[k]] = s.gt_ids[k];
  for (const LabelMap& m : predictions.views) {
    const int vi = capture.find_view(m.view);
    if (vi < 0 || !capture.views[vi].held_out || !capture.views[vi].gt_instance.present()) continue;
    const View& view = capture.views[vi];
    const cv::Mat3b render_rgb =
        channel_image(render(model, view.camera, view.pose, RenderSettings{}), "rgb");
    cv::Mat1i predicted = m.labels;
    if (predicted.size() != render_rgb.size())
      cv::resize(m.labels, predicted, render_rgb.size(), 0, 0, cv::INTER_NEAREST);
    const cv::Mat3b picture = instance_comparison_picture(
        view.gt_instance.load(), render_rgb, predicted, pred_to_gt, m.view + " (held out)");
    if (!picture.empty()) write_rgb_png(dir / (m.view + kGtRenderInstancesSuffix), picture);
  }
}

void run_instance_hungarian(NodeContext& ctx, const InstanceEvalOptions&) {
  const auto predictions = ctx.input<LabelMapSet>("predictions");
  const auto capture = ctx.input<Capture>("capture");
  const InstanceScores s = score_label_maps(*predictions, *capture);
  ctx.record("views", static_cast<double>(predictions->views.size()));
  ctx.record("mIoU", 100 * s.miou);
  ctx.record("precision", 100 * s.precision);
  ctx.record("recall", 100 * s.recall);
  ctx.record("gt_labels", static_cast<double>(s.gt_labels));
  ctx.record("pred_labels", static_cast<double>(s.pred_labels));
  ctx.record("hits", static_cast<double>(s.hits));
  if (ctx.has_input("model")) {
    std::vector<int> views;
    for (const LabelMap& m : predictions->views) views.push_back(capture->find_view(m.view));
    ctx.record("psnr", mean_psnr(*ctx.input<GaussianModel>("model"), *capture, views));
  }
  const auto dir = ctx.out_dir();
  if (dir.empty()) return;
  write_file_atomically(dir / "matches.csv", instance_matches_csv(s, *capture));
  if (ctx.has_input("model"))
    write_instance_pictures(*ctx.input<GaussianModel>("model"), *capture, *predictions, s, dir);
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
  write_rgb_png(dir / "confusion.png", confusion_heatmap_captioned(e.all, predictions->classes));
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
  registry.add(NodeSpec{"eval.mask_coverage",
                        "how well automatic masks cover the ground-truth instances: per instance "
                        "the best IoU of any mask of its view, averaged, per granularity and over "
                        "all; masks per view",
                        {{"masks", PortTypeName<MaskSet>::value,
                          "automatic masks (ingest.sam_masks kind auto, masks.auto, "
                          "masks.geometry)"},
                         {"truth", PortTypeName<MaskSet>::value,
                          "ground-truth instance masks (masks.ground_truth)"}},
                        {}},
               ParamTable<MaskCoverageOptions>(), run_mask_coverage);
  registry.add(
      NodeSpec{"eval.instance_hungarian",
               "Gaga eval.py: label maps against ground-truth instances, one-to-one Hungarian "
               "matching; mIoU, precision and recall at IoU > 0.5 (and PSNR with a model)",
               {{"predictions", PortTypeName<LabelMapSet>::value,
                 "label maps of the views to score (held-out: end to end; training: association)"},
                {"capture",
                 PortTypeName<Capture>::value,
                 "views with ground-truth instances",
                 false,
                 {{CaptureItem::GtInstances}}},
                {"model", PortTypeName<GaussianModel>::value,
                 "the reconstruction, for PSNR on the scored views", true}},
               {}},
      ParamTable<InstanceEvalOptions>(), run_instance_hungarian);
  NodeSpec spec{
      "eval.langor",
      "mIoU, mLocAcc and mAcc of text queries on the held-out views (LangOR 4.1, LangSplat)",
      {{"predictions", PortTypeName<TextQueryResults>::value,
        "masks and relevancy maps of the class-name queries (inference.text_query)"},
       {"capture",
        PortTypeName<Capture>::value,
        "held-out views with ground-truth semantics",
        false,
        {{CaptureItem::HeldOutViews}, {CaptureItem::GtSemantics}, {CaptureItem::GtClasses}}}},
      {}};
  registry.add(std::move(spec), langor_eval_param_table(), run_langor_eval);
  registry.add({"eval.semantic",
                "GA, CA, CP of per-pixel class maps on every view with ground truth, training and "
                "held-out views apart (paper 002 §4.2); confusion matrix CSV + PNG",
                {{"predictions", PortTypeName<SemanticMaps>::value, "per-pixel class maps"},
                 {"capture",
                  PortTypeName<Capture>::value,
                  "views with gt/semantic maps",
                  false,
                  {{CaptureItem::GtSemantics}}}},
                {}},
               semantic_eval_param_table(), run_semantic_eval);
}

}  // namespace gslift
