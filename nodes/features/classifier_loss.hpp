// Cross-entropy of rendered features against per-pixel labels, for the two classifiers that
// supervise per-Gaussian features with SAM masks:
//  - Proto-SaGa Eq. 6-7: the cosine classifier of one training view, logits
//    tau cos(w_c, F(p)) = tau w_c.F / (|w_c| |F|), over the view's raw SAM ids;
//  - Gaga's lift (lift.py): a 1x1 linear classifier, logits W F + b, over the consistent labels,
//    its cross-entropy divided by ln(classes) as Gaga does.
// Both are means over the sampled pixels; the gradients are exact (checked by finite differences
// in tests/features/classifier_loss_test.cpp). |F| is the smoothed norm of contrastive_loss.hpp
// (kCosineEps): a pixel no Gaussian covers renders F = 0.
#pragma once

namespace gslift {

// Mean over n pixels of -log softmax(tau cos(w_c, F(p)))_{label(p)}. features: n x dim; labels in
// [0, classes); weights: classes x dim. grad_features (n x dim) is OVERWRITTEN; grad_weights
// (classes x dim) is ADDED to.
double cosine_classifier_loss(const float* features, int n, int dim, const int* labels,
                              const float* weights, int classes, double tau, float* grad_features,
                              float* grad_weights);

// Mean over n pixels of -log softmax(W F(p) + b)_{label(p)} / ln(classes) (Gaga). grad_features
// OVERWRITTEN; grad_weights (classes x dim) and grad_bias (classes) ADDED to.
double linear_classifier_loss(const float* features, int n, int dim, const int* labels,
                              const float* weights, const float* bias, int classes,
                              float* grad_features, float* grad_weights, float* grad_bias);

}  // namespace gslift
