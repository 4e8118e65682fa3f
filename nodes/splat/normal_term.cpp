// The normal term: 1 - cos between the rendered normals and the normals of the depth prior.
#include "nodes/splat/loss_terms.hpp"
#include "nodes/splat/losses.hpp"

namespace gslift {
namespace {

class NormalTerm : public LossTerm {
 public:
  explicit NormalTerm(double weight) : LossTerm(weight, {}) {}
  const char* name() const override { return "normal"; }
  TermStage stage() const override { return TermStage::Image; }
  void request(RenderSettings& settings) const override { settings.normal = true; }
  double evaluate(const StepRender& s, RenderGrads& image, ModelGrads&) override {
    cv::Mat grad;
    const cv::Mat rendered(s.out.height, s.out.width, CV_32FC3,
                           const_cast<float*>(s.out.normal.data()));
    const double value = normal_cosine_loss(rendered, s.target.normals, &grad);
    add_scaled(image.normal, grad, weight());
    return value;
  }

 protected:
  bool has_target(const TargetImages& t) const override { return !t.normals.empty(); }
};

}  // namespace

std::unique_ptr<LossTerm> normal_term(const ReconstructOptions& o, const TermSetup&) {
  if (!(o.normal_weight > 0)) return nullptr;
  return std::make_unique<NormalTerm>(o.normal_weight);
}

}  // namespace gslift
