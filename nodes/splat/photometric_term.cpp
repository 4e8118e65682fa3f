// The photometric term: 3DGS's (1 - lambda) L1 + lambda D-SSIM against the view's image, always on.
#include "nodes/splat/loss_terms.hpp"
#include "nodes/splat/losses.hpp"

namespace gslift {
namespace {

class PhotometricTerm : public LossTerm {
 public:
  explicit PhotometricTerm(double ssim_lambda) : LossTerm(1.0, {}), ssim_lambda_(ssim_lambda) {}
  const char* name() const override { return "photometric"; }
  TermStage stage() const override { return TermStage::Image; }
  double evaluate(const StepRender& s, RenderGrads& image, ModelGrads&) override {
    cv::Mat grad;
    const cv::Mat rendered(s.out.height, s.out.width, CV_32FC3,
                           const_cast<float*>(s.out.rgb.data()));
    const double value = photometric_loss(rendered, *s.target.ssim, ssim_lambda_, &grad).value;
    add_scaled(image.rgb, grad, weight());
    return value;
  }

 private:
  double ssim_lambda_;
};

}  // namespace

std::unique_ptr<LossTerm> photometric_term(const ReconstructOptions& o, const TermSetup&) {
  return std::make_unique<PhotometricTerm>(o.ssim_lambda);
}

}  // namespace gslift
