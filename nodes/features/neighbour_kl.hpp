// Gaga's optional 3D neighbour regulariser (lift.py's L_3d, Gaussian Grouping's loss_cls_3d;
// method-anchors §1.1 step 4): the class distributions of Gaussians that are close in space
// should agree. Every `interval` steps `samples` Gaussians are drawn, the k nearest Gaussian
// centres of each found (the sample itself included, at distance 0, as torch.cdist + topk do),
// and the loss is
//   L_3d = lambda / C * mean over (sample s, neighbour j) of KL(p_s || p_j),
//   KL(p || q) = sum_c p_c (log(p_c + 1e-10) - log(q_c + 1e-10)),
// with p = softmax(W f + b) the 1x1 classifier applied to the Gaussian's own feature f and C the
// number of classes. Gaga (config/train.json): k 5, lambda 2, every 5 steps, 1000 samples; its
// subsampling of models above 200k Gaussians (reg3d_max_points) is not done: the tree holds
// every Gaussian.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

namespace gslift {

struct NeighbourKlOptions {
  double lambda = 0;   // 0 = off (Gaga's code: 2)
  int k = 5;           // neighbours per sample, the sample itself included (Gaga: 5)
  int interval = 5;    // the loss joins every this many steps (Gaga: 5)
  int samples = 1000;  // Gaussians drawn per regularised step (Gaga: 1000)
};

// A KD-tree over the Gaussian centres (N x 3), fixed geometry.
class GaussianNeighbours {
 public:
  explicit GaussianNeighbours(const std::vector<float>& means);
  ~GaussianNeighbours();
  // The k nearest centres of each of `queries` (indices into the centres), nearest first,
  // samples x k row-major (fewer than k centres: padded with the last one found).
  std::vector<int> nearest(const std::vector<int>& queries, int k) const;

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
  size_t n_ = 0;
};

// L_3d for the given samples and their neighbours (samples.size() x k) over per-Gaussian features
// (N x dim) and the classifier W (classes x dim), b (classes). Gradients ADDED to grad_features
// (N x dim), grad_weights and grad_bias; returns the loss (lambda included).
double neighbour_kl_loss(const float* features, int dim, const float* weights, const float* bias,
                         int classes, const std::vector<int>& samples,
                         const std::vector<int>& neighbours, int k, double lambda,
                         float* grad_features, float* grad_weights, float* grad_bias);

}  // namespace gslift
