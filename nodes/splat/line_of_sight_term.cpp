// The line-of-sight term (line_of_sight_loss.hpp): the opacity each pixel of the step's view
// draws in front of its depth prior, on its schedule (short runs lose their surfaces when it
// joins early: bench/splat_recon/README.md).
#include "nodes/splat/line_of_sight_loss.hpp"
#include "nodes/splat/loss_terms.hpp"

namespace gslift {
namespace {

class LineOfSightTerm : public LossTerm {
 public:
  LineOfSightTerm(double weight, TermSchedule schedule, double tolerance, bool ray_depth)
      : LossTerm(weight, schedule), tolerance_(tolerance), ray_depth_(ray_depth) {}
  const char* name() const override { return "line_of_sight"; }
  TermStage stage() const override { return TermStage::Ray; }
  double evaluate(const StepRender& s, RenderGrads&, ModelGrads& model) override {
    return line_of_sight_loss(s.model, s.camera, s.pose, s.target.depth, s.out, tolerance_,
                              weight(), &model, ray_depth_);
  }

 protected:
  bool has_target(const TargetImages& t) const override { return !t.depth.empty(); }

 private:
  double tolerance_;
  bool ray_depth_;
};

}  // namespace

std::unique_ptr<LossTerm> line_of_sight_term(const ReconstructOptions& o, const TermSetup&) {
  if (!(o.line_of_sight_weight > 0)) return nullptr;
  return std::make_unique<LineOfSightTerm>(o.line_of_sight_weight,
                                           TermSchedule{o.line_of_sight_start, 1},
                                           o.floaters.tolerance, o.floaters.ray_depth);
}

}  // namespace gslift
