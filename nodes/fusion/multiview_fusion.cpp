#include "nodes/fusion/multiview_fusion.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <tbb/parallel_for.h>
#include <Eigen/Geometry>

#include "base/errors.hpp"
#include "nodes/fusion/capture_views.hpp"

namespace gslift {
namespace {

void check_frame(const FusionFrame& f, int index, int classes) {
  const int w = f.camera.width, h = f.camera.height;
  if (f.depth.cols != w || f.depth.rows != h)
    throw InputError("fusion.multiview: frame " + std::to_string(index) + " has a " +
                     std::to_string(f.depth.cols) + "x" + std::to_string(f.depth.rows) +
                     " depth for a " + std::to_string(w) + "x" + std::to_string(h) + " camera");
  if (!f.semantics || f.semantics->probabilities.size() != size_t(w) * h * classes ||
      f.semantics->labels.cols != w || f.semantics->labels.rows != h)
    throw InputError("fusion.multiview: frame " + std::to_string(index) +
                     " has semantics of another size than its " + std::to_string(w) + "x" +
                     std::to_string(h) + " camera");
}

// Camera-space point of pixel (u, v) at depth z (pixel centres at +0.5, camera.hpp).
Eigen::Vector3d unproject(const Camera& c, int u, int v, double z) {
  return {(u + 0.5 - c.cx) / c.fx * z, (v + 0.5 - c.cy) / c.fy * z, z};
}

// x_b = R x_a + t: frame a's camera coordinates into frame b's.
struct Rigid {
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  Eigen::Vector3d operator()(const Eigen::Vector3d& x) const { return R * x + t; }
};

Rigid relative(const Pose& from, const Pose& to) {
  // x_w = R_a^T (x_a - t_a); x_b = R_b x_w + t_b.
  Rigid r;
  r.R = to.R * from.R.transpose();
  r.t = to.t - r.R * from.t;
  return r;
}

}  // namespace

MultiviewFusionResult fuse_multiview(const std::vector<FusionFrame>& frames, int reference,
                                     int classes, const MultiviewFusionOptions& options) {
  multiview_fusion_param_table().validate(options, "fusion.multiview");
  for (size_t i = 0; i < frames.size(); ++i) check_frame(frames[i], static_cast<int>(i), classes);
  const FusionFrame& ref = frames.at(static_cast<size_t>(reference));
  const int w = ref.camera.width, h = ref.camera.height;
  std::vector<Rigid> to_other(frames.size()), to_ref(frames.size());
  for (size_t i = 0; i < frames.size(); ++i) {
    to_other[i] = relative(ref.pose, frames[i].pose);
    to_ref[i] = relative(frames[i].pose, ref.pose);
  }

  MultiviewFusionResult result;
  SemanticView& out = result.fused;
  out.view = ref.semantics->view;
  out.probabilities = ref.semantics->probabilities;
  out.labels = ref.semantics->labels.clone();
  out.confidence = ref.semantics->confidence.clone();
  std::atomic<long long> contributions{0}, changed{0};
  const int r = options.neighbourhood;
  tbb::parallel_for(0, h, [&](int v) {
    std::vector<double> product(classes);
    std::vector<int> votes(classes + 1);  // votes[label + 1]: label -1 (no information) too
    long long row_contributions = 0, row_changed = 0;
    for (int u = 0; u < w; ++u) {
      const float z = ref.depth(v, u);
      if (!(z > 0)) continue;
      const int p = v * w + u;
      const float* own = ref.semantics->pixel(p, classes);
      std::copy(own, own + classes, product.begin());
      const Eigen::Vector3d point = unproject(ref.camera, u, v, z);
      for (size_t i = 0; i < frames.size(); ++i) {
        if (static_cast<int>(i) == reference) continue;
        const FusionFrame& f = frames[i];
        const Eigen::Vector3d x = to_other[i](point);
        if (!(x.z() > 0)) continue;
        const double fu = f.camera.fx * x.x() / x.z() + f.camera.cx;
        const double fv = f.camera.fy * x.y() / x.z() + f.camera.cy;
        if (!(fu >= 0 && fv >= 0 && fu < f.camera.width && fv < f.camera.height)) continue;
        const int cu = static_cast<int>(fu), cv_ = static_cast<int>(fv);
        // Moore neighbourhood, each neighbour validated in the reference frame (Eq. 1).
        std::fill(votes.begin(), votes.end(), 0);
        int valid = 0;
        bool centre_valid = false;
        for (int dy = -r; dy <= r; ++dy)
          for (int dx = -r; dx <= r; ++dx) {
            const int nu = cu + dx, nv = cv_ + dy;
            if (nu < 0 || nv < 0 || nu >= f.camera.width || nv >= f.camera.height) continue;
            const float nz = f.depth(nv, nu);
            if (!(nz > 0)) continue;
            const Eigen::Vector3d back = to_ref[i](unproject(f.camera, nu, nv, nz));
            if (!(std::abs(back.z() - z) < options.epsilon)) continue;
            ++votes[f.semantics->labels(nv, nu) + 1];
            ++valid;
            if (dx == 0 && dy == 0) centre_valid = true;
          }
        if (valid == 0) continue;
        int best = 0;
        for (int k = 1; k <= classes; ++k)
          if (votes[k] > votes[best]) best = k;
        const int centre_label = f.semantics->labels(cv_, cu);
        if (centre_valid && votes[centre_label + 1] == votes[best]) best = centre_label + 1;
        const int majority = best - 1;
        // The distribution of the neighbour that carries the majority label.
        int source = -1;
        if (centre_valid && centre_label == majority) {
          source = cv_ * f.camera.width + cu;
        } else {
          for (int dy = -r; dy <= r && source < 0; ++dy)
            for (int dx = -r; dx <= r && source < 0; ++dx) {
              const int nu = cu + dx, nv = cv_ + dy;
              if (nu < 0 || nv < 0 || nu >= f.camera.width || nv >= f.camera.height) continue;
              const float nz = f.depth(nv, nu);
              if (!(nz > 0) || f.semantics->labels(nv, nu) != majority) continue;
              const Eigen::Vector3d back = to_ref[i](unproject(f.camera, nu, nv, nz));
              if (std::abs(back.z() - z) < options.epsilon) source = nv * f.camera.width + nu;
            }
        }
        const float* m = f.semantics->pixel(source, classes);
        double sum = 0;
        for (int j = 0; j < classes; ++j) sum += product[j] * m[j];
        if (!(sum > 0)) continue;
        for (int j = 0; j < classes; ++j) product[j] = product[j] * m[j] / sum;
        ++row_contributions;
      }
      float* d = out.pixel(p, classes);
      int label = 0;
      for (int j = 0; j < classes; ++j) {
        d[j] = static_cast<float>(product[j]);
        if (product[j] > product[label]) label = j;
      }
      // Parity keeps the reference label (paper 002 §3.2).
      const int own_label = ref.semantics->labels(v, u);
      if (own_label >= 0 && product[own_label] == product[label]) label = own_label;
      if (label != own_label) ++row_changed;
      out.labels(v, u) = label;
      out.confidence(v, u) = d[label];
    }
    contributions += row_contributions;
    changed += row_changed;
  });
  result.contributions = contributions;
  result.changed = changed;
  return result;
}

SemanticMaps fuse_multiview_maps(const SemanticMaps& in, const Capture& capture,
                                 const MultiviewFusionOptions& o, long long* contributions,
                                 long long* changed) {
  std::vector<FusionFrame> frames(in.views.size());
  for (size_t v = 0; v < frames.size(); ++v) {
    const View& view = capture_view(capture, in.views[v], "fusion.multiview");
    frames[v] = {view.camera, view.pose, depth_prior(view, "fusion.multiview"), &in.views[v]};
  }
  SemanticMaps out;
  out.classes = in.classes;
  out.views.resize(frames.size());
  std::atomic<long long> sum_contributions{0}, sum_changed{0};
  tbb::parallel_for(size_t(0), frames.size(), [&](size_t v) {
    MultiviewFusionResult r = fuse_multiview(frames, static_cast<int>(v), in.class_count(), o);
    sum_contributions += r.contributions;
    sum_changed += r.changed;
    out.views[v] = std::move(r.fused);
  });
  if (contributions) *contributions = sum_contributions;
  if (changed) *changed = sum_changed;
  return out;
}

const ParamTable<MultiviewFusionOptions>& multiview_fusion_param_table() {
  using O = MultiviewFusionOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("epsilon", &O::epsilon,
               "geometric validation: max depth difference in the reference camera, metres "
               "(paper 002 Eq. 1: 0.05)",
               0, 100)
          .add("neighbourhood", &O::neighbourhood,
               "half-width of the Moore neighbourhood that votes (1 = 3x3, the paper's)", 0, 5);
  return table;
}

}  // namespace gslift
