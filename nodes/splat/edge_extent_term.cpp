// The edge-extent term (depth_edge_extent.hpp): the extent along the training rays of the
// Gaussians at the depth priors' silhouettes, over every training view at each step.
#include "nodes/splat/depth_edge_extent.hpp"
#include "nodes/splat/loss_terms.hpp"
#include "nodes/splat/view_geometry.hpp"

namespace gslift {
namespace {

class EdgeExtentTerm : public LossTerm {
 public:
  EdgeExtentTerm(double weight, const std::vector<DepthObservation>& observations, double tolerance)
      : LossTerm(weight, {}),
        observations_(observations),
        // Where the priors jump by more than 10%: the training views' silhouettes.
        edges_(depth_edges(observations, 0.1, kDiscontinuityRadius)),
        tolerance_(tolerance) {}
  const char* name() const override { return "edge_extent"; }
  TermStage stage() const override { return TermStage::Model; }
  double evaluate(const StepRender& s, RenderGrads&, ModelGrads& model) override {
    const double value = depth_edge_extent_loss(s.model, observations_, edges_, tolerance_, &grad_);
    add_scaled(model.log_scales, grad_, weight());
    return value;
  }

 private:
  const std::vector<DepthObservation>& observations_;
  std::vector<DepthEdgeView> edges_;
  double tolerance_;
  std::vector<float> grad_;
};

}  // namespace

std::unique_ptr<LossTerm> edge_extent_term(const ReconstructOptions& o, const TermSetup& s) {
  if (!(o.edge_extent_weight > 0)) return nullptr;
  return std::make_unique<EdgeExtentTerm>(o.edge_extent_weight, s.observations,
                                          o.floaters.tolerance);
}

}  // namespace gslift
