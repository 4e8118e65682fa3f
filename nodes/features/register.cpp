#include "nodes/features/register.hpp"

#include <cmath>

#include "base/errors.hpp"
#include "nodes/features/contrastive_features.hpp"
#include "nodes/features/correspondence_features.hpp"
#include "nodes/features/label_classifier.hpp"
#include "nodes/features/view_classifiers.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/label_maps.hpp"
#include "nodes/scene/masks.hpp"
#include "nodes/splat/ply_io.hpp"

namespace gslift {
namespace {

void run_contrastive(NodeContext& ctx, ContrastiveOptions o) {
  o.seed = ctx.seed();
  ContrastiveResult r =
      train_contrastive_features(*ctx.input<GaussianModel>("model"), *ctx.input<Capture>("capture"),
                                 *ctx.input<MaskSet>("masks"), o, [&](const TrainingStep& step) {
                                   ctx.check_cancelled();
                                   ctx.progress(step);
                                 });
  ctx.record("masks", r.masks);
  ctx.record("loss_start", r.loss_start);
  ctx.record("loss_end", r.loss_end);
  ctx.record("cache_bytes", static_cast<double>(r.cache_bytes));
  ctx.record("seconds", r.seconds);
  ctx.output("model", std::move(r.model));
}

void add_contrastive(Registry& registry) {
  NodeSpec spec{
      "features.contrastive",
      "mask-aware contrastive instance features on frozen geometry (LangOR Eq. 3)",
      {{"model", PortTypeName<GaussianModel>::value, "reconstructed Gaussians (geometry kept)"},
       {"capture", PortTypeName<Capture>::value, "posed views; only training views are used"},
       {"masks", PortTypeName<MaskSet>::value, "instance masks per view (e.g. boxes.to_masks)"}},
      {{"model", PortTypeName<GaussianModel>::value,
        "the same Gaussians with dim trained feature channels"}}};
  registry.add(std::move(spec), contrastive_param_table(), run_contrastive);
}

void run_correspondence(NodeContext& ctx, CorrespondenceOptions o) {
  o.seed = ctx.seed();
  CorrespondenceResult r = train_correspondence_features(
      *ctx.input<GaussianModel>("model"), *ctx.input<Capture>("capture"),
      *ctx.input<MaskSet>("masks"), o, [&](const TrainingStep& step) {
        ctx.check_cancelled();
        ctx.progress(step);
      });
  ctx.record("views", r.views);
  ctx.record("masks", r.masks);
  ctx.record("loss_start", r.loss_start);
  ctx.record("loss_end", r.loss_end);
  ctx.record("cache_bytes", static_cast<double>(r.cache_bytes));
  ctx.record("seconds", r.seconds);
  // The feature model `gslift segment` loads (SAGA saves its contrastive_feature_point_cloud.ply).
  const auto dir = ctx.out_dir();
  if (!dir.empty()) write_ply(r.model, dir / "model.ply");
  ctx.output("model", std::move(r.model));
}

void add_correspondence(Registry& registry) {
  NodeSpec spec{
      "features.correspondence",
      "SAGA affinity features on frozen geometry from multi-granularity masks (correspondence "
      "loss, paper 001 4.2)",
      {{"model", PortTypeName<GaussianModel>::value, "reconstructed Gaussians (geometry kept)"},
       {"capture", PortTypeName<Capture>::value, "posed views; only training views are used"},
       {"masks", PortTypeName<MaskSet>::value,
        "automatic masks per view, overlapping granularities (ingest.sam_masks auto, masks.auto)"}},
      {{"model", PortTypeName<GaussianModel>::value,
        "the same Gaussians with dim trained affinity channels (file: model.ply, what gslift "
        "segment loads)"}}};
  registry.add(std::move(spec), correspondence_param_table(), run_correspondence);
}

void run_view_classifiers(NodeContext& ctx, ViewClassifierOptions o) {
  o.seed = ctx.seed();
  const bool joint = o.training == FeatureTraining::Joint;
  if (joint == ctx.has_input("model"))
    throw InputError(joint ? "training: joint reconstructs the capture itself (the recon_* "
                             "params): leave the model input unconnected"
                           : "training: frozen needs the model input (the reconstruction)");
  const auto progress = [&](const TrainingStep& step) {
    ctx.check_cancelled();
    ctx.progress(step);
  };
  const Capture& capture = *ctx.input<Capture>("capture");
  const LabelMapSet& partitions = *ctx.input<LabelMapSet>("partitions");
  ViewClassifierResult r = joint ? train_view_classifiers_jointly(capture, partitions, o, progress)
                                 : train_view_classifiers(*ctx.input<GaussianModel>("model"),
                                                          capture, partitions, o, progress);
  if (r.recon) {
    ctx.record("gaussians", static_cast<double>(r.model.size()));
    ctx.record("train_psnr", r.recon->train_psnr);
    ctx.record("depth_prior_views", static_cast<double>(r.recon->depth_prior_views));
    if (!std::isnan(r.recon->test_psnr)) ctx.record("test_psnr", r.recon->test_psnr);
    // Each term's final loss, as splat.reconstruct records them (which terms a recipe turned on).
    for (const auto& [term, value] : r.recon->final_loss.terms) ctx.record("loss_" + term, value);
  }
  ctx.record("views", static_cast<double>(r.classifiers.views.size()));
  ctx.record("loss_start", r.loss_start);
  ctx.record("loss_end", r.loss_end);
  ctx.record("cache_bytes", static_cast<double>(r.cache_bytes));
  ctx.record("seconds", r.seconds);
  ctx.output("model", std::move(r.model));
  ctx.output("classifiers", std::move(r.classifiers));
}

void run_label_classifier(NodeContext& ctx, LabelClassifierOptions o) {
  o.seed = ctx.seed();
  LabelClassifierResult r =
      train_label_classifier(*ctx.input<GaussianModel>("model"), *ctx.input<Capture>("capture"),
                             *ctx.input<LabelMapSet>("labels"), o, [&](const TrainingStep& step) {
                               ctx.check_cancelled();
                               ctx.progress(step);
                             });
  ctx.record("classes", static_cast<double>(r.classifier.classes));
  ctx.record("loss_start", r.loss_start);
  ctx.record("loss_end", r.loss_end);
  ctx.record("seconds", r.seconds);
  ctx.output("model", std::move(r.model));
  ctx.output("classifier", std::move(r.classifier));
}

void add_classifiers(Registry& registry) {
  registry.add(
      NodeSpec{"features.view_classifiers",
               "Proto-SaGa Eq. 6-8, frozen geometry or joint with the reconstruction: "
               "per-Gaussian features and one cosine classifier per training view over its raw "
               "SAM ids",
               {{"model", PortTypeName<GaussianModel>::value,
                 "reconstructed Gaussians, kept (frozen); unconnected for joint", true},
                {"capture", PortTypeName<Capture>::value, "posed views; training views are used"},
                {"partitions", PortTypeName<LabelMapSet>::value,
                 "raw SAM id maps (association.sam_partition)"}},
               {{"model", PortTypeName<GaussianModel>::value,
                 "the Gaussians with dim trained feature channels (joint: reconstructed here)"},
                {"classifiers", PortTypeName<ViewClassifiers>::value,
                 "one cosine classifier per training view"}}},
      view_classifier_param_table(), run_view_classifiers);
  registry.add(
      NodeSpec{"features.label_classifier",
               "Gaga's lift on frozen geometry: per-Gaussian features and a linear classifier "
               "trained on the consistent label maps",
               {{"model", PortTypeName<GaussianModel>::value, "reconstructed Gaussians (kept)"},
                {"capture", PortTypeName<Capture>::value, "posed views; training views are used"},
                {"labels", PortTypeName<LabelMapSet>::value,
                 "consistent label maps (association.memory_bank)"}},
               {{"model", PortTypeName<GaussianModel>::value,
                 "the same Gaussians with dim trained feature channels"},
                {"classifier", PortTypeName<LabelClassifier>::value,
                 "the 1x1 classifier over the labels 0..L"}}},
      label_classifier_param_table(), run_label_classifier);
}

}  // namespace

void register_features_nodes(Registry& registry) {
  add_contrastive(registry);
  add_correspondence(registry);
  add_classifiers(registry);
}

}  // namespace gslift
