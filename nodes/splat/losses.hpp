// The training losses of the geometry-constrained reconstruction (3DGS; LangOR §2.3; DN-Splatter).
// Each returns its value and, when asked, its gradient with respect to the rendered quantity,
// unweighted: the training loop scales each by its weight (0 switches a term off for the ablation).
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "nodes/splat/ssim.hpp"

namespace gslift {

struct PhotometricLoss {
  double value = 0;  // (1 - lambda) L1 + lambda (1 - SSIM)
  double l1 = 0;     // mean |rendered - target| over pixels and channels
  double ssim = 0;   // mean SSIM (ssim.hpp)
};

// 3DGS photometric loss (1 - lambda) L1 + lambda D-SSIM with D-SSIM = 1 - SSIM and lambda = 0.2 in
// the paper. Both images CV_32FC3 in [0,1]. grad receives dL/d(rendered) (CV_32FC3).
// The SsimTarget form reuses the target's windowed statistics (training: once per view).
PhotometricLoss photometric_loss(const cv::Mat& rendered, const SsimTarget& target,
                                 double ssim_lambda, cv::Mat* grad = nullptr);
PhotometricLoss photometric_loss(const cv::Mat& rendered, const cv::Mat& target, double ssim_lambda,
                                 cv::Mat* grad = nullptr);

// DN-Splatter depth loss: mean over valid pixels (target > 0 and finite) of log(1 + |d_hat - d|).
// Both CV_32FC1 metres. Returns 0 (and a zero gradient) when no pixel is valid.
double depth_log_l1_loss(const cv::Mat& rendered, const cv::Mat& target, cv::Mat* grad = nullptr);

// Normal consistency: mean over valid pixels of 1 - cos(n_hat, n), where the target n is a unit
// normal (CV_32FC3, all-zero = invalid) and n_hat the rendered normal (CV_32FC3, a blend of unit
// normals, so not unit itself). Pixels where |n_hat| < 1e-6 (nothing rendered) are skipped.
double normal_cosine_loss(const cv::Mat& rendered, const cv::Mat& target, cv::Mat* grad = nullptr);

// Flatness regulariser (DN-Splatter, LangOR "scale consistency"): mean over Gaussians of the
// smallest scale exp(min_k log_scale_k), pushing each Gaussian towards a disc that follows the
// surface. log_scales is N x 3; grad (resized to N x 3) receives dL/d(log_scales).
double flatness_loss(const std::vector<float>& log_scales, std::vector<float>* grad = nullptr);

}  // namespace gslift
