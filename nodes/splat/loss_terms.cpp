#include "nodes/splat/loss_terms.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace gslift {

namespace {

// f(begin, end) over [0, n) in parallel blocks: the element-wise sums below, which on one thread
// kept the second core idle at every step.
template <class F>
void for_blocks(size_t n, F&& f) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1 << 14),
                    [&](const tbb::blocked_range<size_t>& r) { f(r.begin(), r.end()); });
}

}  // namespace

void add_scaled(std::vector<float>& into, const cv::Mat& image, double weight) {
  const cv::Mat c = image.isContinuous() ? image : image.clone();
  const float* p = c.ptr<float>();
  const size_t n = c.total() * c.channels();
  const float w = static_cast<float>(weight);
  if (into.empty()) {
    into.resize(n);
    for_blocks(n, [&](size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i) into[i] = w * p[i];
    });
  } else {
    for_blocks(n, [&](size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i) into[i] += w * p[i];
    });
  }
}

void add_scaled(std::vector<float>& into, const std::vector<float>& grad, double weight) {
  for_blocks(grad.size(), [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) into[i] += static_cast<float>(weight * grad[i]);
  });
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
