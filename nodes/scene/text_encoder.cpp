#include "nodes/scene/text_encoder.hpp"

namespace gslift {

float cosine(const Eigen::VectorXf& a, const Eigen::VectorXf& b) {
  const float na = a.norm(), nb = b.norm();
  return na > 0 && nb > 0 ? a.dot(b) / (na * nb) : 0.f;
}

}  // namespace gslift
