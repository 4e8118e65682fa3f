#include "nodes/fusion/cluster_smoothing.hpp"

#include <algorithm>
#include <vector>

#include <atomic>

#include <tbb/parallel_for.h>

#include "base/errors.hpp"
#include "nodes/fusion/capture_views.hpp"

namespace gslift {

ClusterSmoothingResult smooth_clusters(const SemanticView& view, const cv::Mat1i& clusters,
                                       int classes) {
  const int w = clusters.cols, h = clusters.rows, n = w * h;
  if (view.labels.cols != w || view.labels.rows != h ||
      view.probabilities.size() != size_t(n) * classes)
    throw InputError("fusion.cluster_smoothing: view '" + view.view + "' is " +
                     std::to_string(view.labels.cols) + "x" + std::to_string(view.labels.rows) +
                     " but its clusters are " + std::to_string(w) + "x" + std::to_string(h));
  int count = 0;
  for (int p = 0; p < n; ++p) count = std::max(count, clusters(p / w, p % w) + 1);
  std::vector<int> votes(size_t(count) * classes, 0);
  for (int p = 0; p < n; ++p) {
    const int c = clusters(p / w, p % w), l = view.labels(p / w, p % w);
    if (c >= 0 && l >= 0) ++votes[size_t(c) * classes + l];
  }
  std::vector<int> majority(count, -1);
  ClusterSmoothingResult result;
  for (int c = 0; c < count; ++c) {
    const int* v = votes.data() + size_t(c) * classes;
    const int best = static_cast<int>(std::max_element(v, v + classes) - v);
    if (v[best] > 0) {
      majority[c] = best;
      ++result.clusters;
    }
  }
  // Mean distribution of the pixels that carry their cluster's majority label.
  std::vector<double> mean(size_t(count) * classes, 0.0);
  for (int p = 0; p < n; ++p) {
    const int c = clusters(p / w, p % w);
    if (c < 0 || majority[c] < 0 || view.labels(p / w, p % w) != majority[c]) continue;
    const float* d = view.pixel(p, classes);
    for (int j = 0; j < classes; ++j) mean[size_t(c) * classes + j] += d[j];
  }
  SemanticView& out = result.smoothed;
  out = view;
  out.labels = view.labels.clone();
  out.confidence = view.confidence.clone();
  for (int c = 0; c < count; ++c) {
    const int m = majority[c];
    if (m < 0) continue;
    double* d = mean.data() + size_t(c) * classes;
    const double total = votes[size_t(c) * classes + m];
    for (int j = 0; j < classes; ++j) d[j] /= total;
  }
  for (int p = 0; p < n; ++p) {
    const int c = clusters(p / w, p % w);
    if (c < 0 || majority[c] < 0) continue;
    const double* d = mean.data() + size_t(c) * classes;
    float* o = out.pixel(p, classes);
    for (int j = 0; j < classes; ++j) o[j] = static_cast<float>(d[j]);
    if (out.labels(p / w, p % w) != majority[c]) ++result.changed;
    out.labels(p / w, p % w) = majority[c];
    out.confidence(p / w, p % w) = o[majority[c]];
  }
  return result;
}

SemanticMaps smooth_cluster_maps(const SemanticMaps& in, const Capture& capture,
                                 const SupervoxelOptions& o, long long* clusters,
                                 long long* changed) {
  SemanticMaps out;
  out.classes = in.classes;
  out.views.resize(in.views.size());
  std::atomic<long long> sum_clusters{0}, sum_changed{0};
  tbb::parallel_for(size_t(0), in.views.size(), [&](size_t v) {
    const View& view = capture_view(capture, in.views[v], "fusion.cluster_smoothing");
    const cv::Mat rgb = view.rgb.load();
    if (rgb.empty())
      throw InputError("fusion.cluster_smoothing: view '" + view.name + "' has no RGB image");
    const cv::Mat1i segments =
        oversegment_rgbd(rgb, depth_prior(view, "fusion.cluster_smoothing"), view.camera, o);
    ClusterSmoothingResult r = smooth_clusters(in.views[v], segments, in.class_count());
    sum_clusters += r.clusters;
    sum_changed += r.changed;
    out.views[v] = std::move(r.smoothed);
  });
  if (clusters) *clusters = sum_clusters;
  if (changed) *changed = sum_changed;
  return out;
}

}  // namespace gslift
