#include "nodes/scene/gaussian_model.hpp"

namespace gslift {

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

}  // namespace gslift
