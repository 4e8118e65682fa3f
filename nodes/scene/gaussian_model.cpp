#include "nodes/scene/gaussian_model.hpp"

#include <Eigen/Geometry>

namespace gslift {

Eigen::Matrix3d GaussianModel::rotation(size_t i) const {
  const float* q = &quats[i * 4];
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
}

void GaussianModel::resize(size_t n) {
  const size_t old = size();
  means.resize(n * 3, 0.f);
  log_scales.resize(n * 3, 0.f);
  quats.resize(n * 4, 0.f);
  for (size_t i = old; i < n; ++i) quats[i * 4] = 1.f;
  opacity_logits.resize(n, 0.f);
  sh.resize(n * sh_coeffs(sh_degree) * 3, 0.f);
  features.resize(n * feature_dim, 0.f);
  if (!instance_ids.empty()) instance_ids.resize(n, -1);
  if (!class_ids.empty()) class_ids.resize(n, -1);
}

namespace {
template <class T>
std::vector<T> gather(const std::vector<T>& from, size_t width, const std::vector<size_t>& rows) {
  std::vector<T> out;
  if (from.empty()) return out;
  out.reserve(rows.size() * width);
  for (size_t r : rows)
    out.insert(out.end(), from.begin() + r * width, from.begin() + (r + 1) * width);
  return out;
}
}  // namespace

GaussianModel GaussianModel::subset(const std::vector<size_t>& indices) const {
  GaussianModel out;
  out.sh_degree = sh_degree;
  out.feature_dim = feature_dim;
  out.means = gather(means, 3, indices);
  out.log_scales = gather(log_scales, 3, indices);
  out.quats = gather(quats, 4, indices);
  out.opacity_logits = gather(opacity_logits, 1, indices);
  out.sh = gather(sh, size_t(sh_coeffs(sh_degree)) * 3, indices);
  out.features = gather(features, size_t(feature_dim), indices);
  out.instance_ids = gather(instance_ids, 1, indices);
  out.class_ids = gather(class_ids, 1, indices);
  return out;
}

}  // namespace gslift
