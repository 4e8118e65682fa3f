#include "nodes/fusion/bayesian_fusion.hpp"

#include <atomic>

#include <tbb/parallel_for.h>

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

SemanticMaps fuse_bayesian_maps(const SemanticMaps& a, const SemanticMaps& b, long long* changed) {
  if (a.classes != b.classes || a.views.size() != b.views.size())
    throw InputError("fusion.bayesian: the two sources differ in classes (" +
                     std::to_string(a.class_count()) + " and " + std::to_string(b.class_count()) +
                     ") or views (" + std::to_string(a.views.size()) + " and " +
                     std::to_string(b.views.size()) + ")");
  SemanticMaps out;
  out.classes = a.classes;
  out.views.resize(a.views.size());
  std::atomic<long long> count{0};
  tbb::parallel_for(size_t(0), a.views.size(), [&](size_t v) {
    const SemanticView& x = a.views[v];
    if (b.views[v].view != x.view)
      throw InputError("fusion.bayesian: view " + std::to_string(v) + " is '" + x.view +
                       "' in one source and '" + b.views[v].view + "' in the other");
    out.views[v] = fuse_bayesian(x, b.views[v], out.class_count(), x.labels.cols, x.labels.rows);
    count += cv::countNonZero(out.views[v].labels != x.labels);
  });
  if (changed) *changed = count;
  return out;
}

}  // namespace gslift
