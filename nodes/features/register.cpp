#include "nodes/features/register.hpp"

#include "nodes/features/contrastive_features.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/masks.hpp"

namespace gslift {
namespace {

void add_contrastive(Registry& registry) {
  const ContrastiveOptions d;
  NodeSpec spec{
      "features.contrastive",
      "mask-aware contrastive instance features on frozen geometry (LangOR Eq. 3)",
      {{"model", PortTypeName<GaussianModel>::value, "reconstructed Gaussians (geometry kept)"},
       {"capture", PortTypeName<Capture>::value, "posed views; only training views are used"},
       {"masks", PortTypeName<MaskSet>::value, "instance masks per view (e.g. boxes.to_masks)"}},
      {{"model", PortTypeName<GaussianModel>::value,
        "the same Gaussians with dim trained feature channels"}},
      {int_param("iterations", d.iterations, "Adam steps (LangOR: 300)", 1, 1e6),
       float_param("lambda", d.lambda, "weight of the outside-mask repulsion (LangOR: 0.2)", 0),
       int_param("dim", d.dim, "feature channels per Gaussian", 1, 512),
       float_param("lr", d.lr, "Adam learning rate of the features", 1e-9, 10),
       int_param("pixels_per_iteration", d.pixels_per_iteration,
                 "pixels sampled inside each mask per step, and as many outside", 1, 1e6),
       float_param("init_std", d.init_std, "standard deviation of the random initial features",
                   1e-9, 100),
       float_param("min_weight", d.min_weight,
                   "blend weights below this are dropped from the stored rows (memory)", 0, 1)}};
  registry.add(std::move(spec), [](NodeContext& ctx) {
    ContrastiveOptions o;
    o.iterations = static_cast<int>(ctx.param_int("iterations"));
    o.lambda = ctx.param_float("lambda");
    o.dim = static_cast<int>(ctx.param_int("dim"));
    o.lr = ctx.param_float("lr");
    o.pixels_per_iteration = static_cast<int>(ctx.param_int("pixels_per_iteration"));
    o.init_std = ctx.param_float("init_std");
    o.min_weight = ctx.param_float("min_weight");
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
  });
}

}  // namespace

void register_features_nodes(Registry& registry) {
  add_contrastive(registry);
}

}  // namespace gslift
