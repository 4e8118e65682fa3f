// The flatness term (DN-Splatter; LangOR's scale consistency): the mean smallest scale.
#include "nodes/splat/loss_terms.hpp"
#include "nodes/splat/losses.hpp"

namespace gslift {
namespace {

class FlatnessTerm : public LossTerm {
 public:
  explicit FlatnessTerm(double weight) : LossTerm(weight, {}) {}
  const char* name() const override { return "flatness"; }
  TermStage stage() const override { return TermStage::Model; }
  double evaluate(const StepRender& s, RenderGrads&, ModelGrads& model) override {
    const double value = flatness_loss(s.model.log_scales, &grad_);
    add_scaled(model.log_scales, grad_, weight());
    return value;
  }

 private:
  std::vector<float> grad_;  // kept between steps: no allocation per step
};

}  // namespace

std::unique_ptr<LossTerm> flatness_term(const ReconstructOptions& o, const TermSetup&) {
  if (!(o.scale_weight > 0)) return nullptr;
  return std::make_unique<FlatnessTerm>(o.scale_weight);
}

}  // namespace gslift
