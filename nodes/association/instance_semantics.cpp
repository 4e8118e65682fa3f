#include "nodes/association/instance_semantics.hpp"

#include <algorithm>

namespace gslift {

InstanceSemantics choose_instance_semantics(const std::vector<std::string>& mask_labels,
                                            const TextEncoder& encoder) {
  InstanceSemantics out;
  out.embedding = Eigen::VectorXf::Zero(encoder.dim());
  const int n = static_cast<int>(mask_labels.size());
  if (n == 0) return out;
  std::vector<Eigen::VectorXf> embeddings;
  for (const std::string& label : mask_labels) embeddings.push_back(encoder.encode(label));

  if (n <= 2) {
    for (const Eigen::VectorXf& e : embeddings) out.embedding += e;
    const float norm = out.embedding.norm();
    if (norm > 0) out.embedding /= norm;
    int best_count = 0;
    for (const std::string& label : mask_labels) {
      const int count = static_cast<int>(std::count(mask_labels.begin(), mask_labels.end(), label));
      if (count > best_count) {
        best_count = count;
        out.label = label;
      }
    }
    return out;
  }

  int best = 0;
  float best_sum = -1e30f;
  for (int i = 0; i < n; ++i) {
    float sum = 0;
    for (int j = 0; j < n; ++j)
      if (j != i) sum += cosine(embeddings[i], embeddings[j]);
    if (sum > best_sum) {
      best_sum = sum;
      best = i;
    }
  }
  out.label = mask_labels[best];
  out.embedding = embeddings[best];
  return out;
}

}  // namespace gslift
