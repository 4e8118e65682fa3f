// The depth term (DN-Splatter): log(1 + |rendered depth - prior|) over the prior's valid pixels.
#include "nodes/splat/loss_terms.hpp"
#include "nodes/splat/losses.hpp"

namespace gslift {
namespace {

class DepthTerm : public LossTerm {
 public:
  explicit DepthTerm(double weight) : LossTerm(weight, {}) {}
  const char* name() const override { return "depth"; }
  TermStage stage() const override { return TermStage::Image; }
  void request(RenderSettings& settings) const override { settings.depth = true; }
  double evaluate(const StepRender& s, RenderGrads& image, ModelGrads&) override {
    cv::Mat grad;
    const cv::Mat rendered(s.out.height, s.out.width, CV_32FC1,
                           const_cast<float*>(s.out.depth.data()));
    const double value = depth_log_l1_loss(rendered, s.target.depth, &grad);
    add_scaled(image.depth, grad, weight());
    return value;
  }

 protected:
  bool has_target(const TargetImages& t) const override { return !t.depth.empty(); }
};

}  // namespace

std::unique_ptr<LossTerm> depth_term(const ReconstructOptions& o, const TermSetup&) {
  if (!(o.depth_weight > 0)) return nullptr;
  return std::make_unique<DepthTerm>(o.depth_weight);
}

}  // namespace gslift
