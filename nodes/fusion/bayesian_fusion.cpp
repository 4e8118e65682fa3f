#include "nodes/fusion/bayesian_fusion.hpp"

#include "base/errors.hpp"

namespace gslift {

SemanticView fuse_bayesian(const SemanticView& a, const SemanticView& b, int classes, int width,
                           int height) {
  const size_t n = size_t(width) * height * classes;
  if (a.probabilities.size() != n || b.probabilities.size() != n)
    throw InputError("fusion.bayesian: view '" + a.view + "' has " +
                     std::to_string(a.probabilities.size()) + " and " +
                     std::to_string(b.probabilities.size()) + " probabilities, expected " +
                     std::to_string(n) + " (" + std::to_string(width) + "x" +
                     std::to_string(height) + "x" + std::to_string(classes) + ")");
  SemanticView out;
  out.view = a.view;
  out.probabilities.resize(n);
  for (int p = 0; p < width * height; ++p) {
    const float* pa = a.pixel(p, classes);
    const float* pb = b.pixel(p, classes);
    float* d = out.pixel(p, classes);
    double sum = 0;
    for (int j = 0; j < classes; ++j) sum += double(pa[j]) * pb[j];
    for (int j = 0; j < classes; ++j)
      d[j] = sum > 0 ? static_cast<float>(double(pa[j]) * pb[j] / sum) : 0.5f * (pa[j] + pb[j]);
  }
  set_argmax(out, classes, width, height);
  return out;
}

}  // namespace gslift
