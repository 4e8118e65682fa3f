// The public SAGA v2 code's scale-gated contrastive loss (train_contrastive_feature.py;
// ../shared/reference/method-anchors.md §1.3 "Affinity-feature training"), for one view's sampled
// pixels, with its gradient. What it learns is one feature per Gaussian whose channels a gate
// switches on and off by the 3D scale of the wanted segment: at a small scale two pixels of one
// part agree, at a large scale two pixels of one object do.
//
// For sampled scales s_k (k = 1..S, quantile-normalised to [0, 1]) the gate is
// g_k = sigmoid(a s_k + b) (Linear(1, D) + Sigmoid: a, b in R^D), and pixel p's gated feature
// u_kp = normalize(F_p ⊙ g_k). With gt_k(p, q) in {0, 1} (p and q share a mask at scale s_k) and
// corr_k(p, q) = <u_kp, u_kq>:
//   L = mean_{k, (p,q) in P+} (-w_pq gt_k corr_k) + mean_{k, (p,q) in P-} (w_pq (1 - gt_k)
//   relu(corr_k))
//       + norm_weight (1 - mean_p |F_p|)^2,
// over unordered pairs p < q. P+ holds the pairs whose gt differs across the scales
// ("inconsistent"), the pairs positive at some scale with corr < 0.75 (hard positives) and a
// random share of the pairs positive at every scale; P- the inconsistent ones, the pairs negative
// at some scale with corr > 0.5 (hard negatives) and a random share of the pairs negative at
// every scale. Each random share is (#inconsistent / 2) / #consistent of its kind, counted over
// the full P x P matrix as the code does. w_pq are the pair weights (mask-size balancing, in
// [1, 10]; scale_gated_pair_weights). The hard-pair choice and the relu make L piecewise smooth;
// the gradient is that of the selected pairs' terms.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace gslift {

struct ScaleGatedLoss {
  double loss = 0;
  Eigen::MatrixXf grad_features;  // P x D: dL/dF
  Eigen::VectorXf grad_gate;      // 2D: dL/da, then dL/db
  int positive_pairs = 0, negative_pairs = 0;
};

// features: P x D rendered pixel features F_p. gt: S matrices P x P (0/1, symmetric). scales: S
// quantile-normalised scales. weights: P x P pair weights. gate: 2D values, a then b. The random
// consistent pairs come from a stream seeded by pair_seed. Needs P >= 2 and S >= 1.
ScaleGatedLoss scale_gated_loss(const Eigen::MatrixXf& features,
                                const std::vector<Eigen::MatrixXf>& gt,
                                const std::vector<float>& scales, const Eigen::MatrixXf& weights,
                                const std::vector<float>& gate, double norm_weight,
                                uint64_t pair_seed);

// The code's pair weights: per pixel the mean area of the masks that cover it, m_p;
// w_pq = max(max_{p',q'} m_p' m_q' / (m_p m_q), 1), then min-max rescaled to [1, 10] (all 1 when
// every weight is equal).
Eigen::MatrixXf scale_gated_pair_weights(const std::vector<float>& mean_mask_area);

}  // namespace gslift
