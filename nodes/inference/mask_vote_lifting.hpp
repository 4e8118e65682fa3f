// Closed-form lifting of 2D masks to Gaussians (FlashSplat, Shen et al., ECCV 2024, arXiv
// 2409.08270; docs/references.md). With the geometry frozen, a rendered mask is linear in the
// per-Gaussian labels: pixel p shows sum_i w_i(p) l_i with w_i = alpha_i T_i. The labelling that
// best reproduces binary masks over the views is a weighted majority vote per Gaussian:
//   A_0[i] = sum over views, pixels outside the mask of w_i(p)
//   A_1[i] = sum over views, pixels inside the mask of w_i(p)
// FlashSplat's binary rule (their render.py, not only the paper): L2-normalise (A_0, A_1), add the
// background bias ("slackness", default 0) to the background entry, take the argmax. A Gaussian no
// masked view sees (A_0 = A_1 = 0) is background here whatever the bias (in their code its sign
// decides: a negative bias puts every unseen Gaussian in the object; reference notes section 3.3).
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "nodes/splat/pixel_rows.hpp"

namespace gslift {

// Votes of P binary masks (one per prompt) for N Gaussians, accumulated view by view.
class MaskVotes {
 public:
  MaskVotes(size_t gaussians, size_t prompts);

  // Adds one view: rows = its blend weights per pixel (W x H pixels, row-major, front to back);
  // masks[k] = prompt k's mask in this view (W x H, nonzero = object), or an empty Mat when prompt
  // k has no mask there (that view does not vote for it). Throws std::invalid_argument on a mask
  // of another size or a wrong count.
  void add_view(const PixelRowsView& rows, int width, int height,
                const std::vector<cv::Mat1b>& masks);

  // Per Gaussian, prompt k's object decision under background bias `bias`, and its score
  // A_1 / |A| (0 for unseen Gaussians): the normalised object vote that ranks prompts claiming
  // the same Gaussian.
  std::vector<uint8_t> object(size_t k, double bias, std::vector<float>* score = nullptr) const;

  // Per Gaussian, prompt k's normalised vote balance (A_1 - A_0) / |(A_0, A_1)| in [-1, 1]: 1 =
  // seen only inside the masks, -1 only outside; 0 for unseen Gaussians (PromptSet::vote_balance).
  std::vector<float> balance(size_t k) const;

  double background(size_t g, size_t k) const { return votes_[2 * (g * prompts_ + k)]; }
  double foreground(size_t g, size_t k) const { return votes_[2 * (g * prompts_ + k) + 1]; }

 private:
  size_t gaussians_, prompts_;
  std::vector<double> votes_;  // N x P x 2: background, object
};

}  // namespace gslift
