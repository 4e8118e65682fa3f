#include "nodes/features/register.hpp"

#include "nodes/features/contrastive_features.hpp"
#include "nodes/features/correspondence_features.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/masks.hpp"
#include "nodes/splat/ply_io.hpp"

namespace gslift {
namespace {

void run_contrastive(NodeContext& ctx, ContrastiveOptions o) {
  o.seed = ctx.seed();
  ContrastiveResult r = train_contrastive_features(
      *ctx.input<GaussianModel>("model"), *ctx.input<Capture>("capture"),
      *ctx.input<MaskSet>("masks"), o, [&](int it, int total) {
        ctx.check_cancelled();
        ctx.progress(static_cast<double>(it + 1) / total, "contrastive features");
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
      *ctx.input<MaskSet>("masks"), o, [&](int it, int total) {
        ctx.check_cancelled();
        ctx.progress(static_cast<double>(it + 1) / total, "correspondence features");
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

}  // namespace

void register_features_nodes(Registry& registry) {
  add_contrastive(registry);
  add_correspondence(registry);
}

}  // namespace gslift
