#include "nodes/splat/loss_terms.hpp"

namespace gslift {

void add_scaled(std::vector<float>& into, const cv::Mat& image, double weight) {
  const cv::Mat c = image.isContinuous() ? image : image.clone();
  const float* p = c.ptr<float>();
  const size_t n = c.total() * c.channels();
  const float w = static_cast<float>(weight);
  if (into.empty()) {
    into.resize(n);
    for (size_t i = 0; i < n; ++i) into[i] = w * p[i];
  } else {
    for (size_t i = 0; i < n; ++i) into[i] += w * p[i];
  }
}

void add_scaled(std::vector<float>& into, const std::vector<float>& grad, double weight) {
  for (size_t i = 0; i < grad.size(); ++i) into[i] += static_cast<float>(weight * grad[i]);
}

LossTerms make_loss_terms(const ReconstructOptions& o, const TermSetup& s) {
  using Factory = std::unique_ptr<LossTerm> (*)(const ReconstructOptions&, const TermSetup&);
  static const Factory factories[] = {photometric_term, depth_term,       normal_term,
                                      flatness_term,    edge_extent_term, line_of_sight_term};
  LossTerms terms;
  for (const Factory make : factories)
    if (auto term = make(o, s)) terms.push_back(std::move(term));
  return terms;
}

}  // namespace gslift
