#include "nodes/inference/mask_vote_lifting.hpp"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace gslift {

MaskVotes::MaskVotes(size_t gaussians, size_t prompts)
    : gaussians_(gaussians), prompts_(prompts), votes_(2 * gaussians * prompts, 0.0) {}

void MaskVotes::add_view(const PixelRowsView& rows, int width, int height,
                         const std::vector<cv::Mat1b>& masks) {
  if (masks.size() != prompts_)
    throw std::invalid_argument("mask votes: " + std::to_string(masks.size()) + " masks for " +
                                std::to_string(prompts_) + " prompts");
  for (const cv::Mat1b& m : masks)
    if (!m.empty() && (m.cols != width || m.rows != height))
      throw std::invalid_argument("mask votes: a " + std::to_string(m.cols) + "x" +
                                  std::to_string(m.rows) + " mask for a " + std::to_string(width) +
                                  "x" + std::to_string(height) + " view");
  // One pass over the pixels; every pair adds its weight to one label of each prompt that has a
  // mask here. Serial: each sum takes its terms in pixel and row order, whatever the thread count.
  // The masks' labels are read once per pixel, not once per pair (the pairs are ~20 per pixel).
  std::vector<size_t> voting;
  for (size_t k = 0; k < prompts_; ++k)
    if (!masks[k].empty()) voting.push_back(k);
  if (voting.empty()) return;
  std::vector<const uint8_t*> row(voting.size());
  std::vector<size_t> slot(voting.size());  // the label's offset in a Gaussian's votes
  for (int y = 0; y < height; ++y) {
    for (size_t i = 0; i < voting.size(); ++i) row[i] = masks[voting[i]].ptr<uint8_t>(y);
    for (int x = 0; x < width; ++x) {
      for (size_t i = 0; i < voting.size(); ++i) slot[i] = 2 * voting[i] + (row[i][x] ? 1 : 0);
      const size_t p = size_t(y) * width + x;
      for (uint32_t e = rows.offsets[p]; e < rows.offsets[p + 1]; ++e) {
        double* v = &votes_[2 * size_t(rows.ids[e]) * prompts_];
        const double w = rows.weights[e];
        for (const size_t s : slot) v[s] += w;
      }
    }
  }
}

std::vector<uint8_t> MaskVotes::object(size_t k, double bias, std::vector<float>* score) const {
  std::vector<uint8_t> out(gaussians_, 0);
  if (score) score->assign(gaussians_, 0.f);
  for (size_t g = 0; g < gaussians_; ++g) {
    const double a0 = background(g, k), a1 = foreground(g, k);
    const double norm = std::hypot(a0, a1);
    if (norm <= 0) continue;
    out[g] = a1 / norm > a0 / norm + bias;
    if (score) (*score)[g] = static_cast<float>(a1 / norm);
  }
  return out;
}

std::vector<float> MaskVotes::balance(size_t k) const {
  std::vector<float> out(gaussians_, 0.f);
  for (size_t g = 0; g < gaussians_; ++g) {
    const double a0 = background(g, k), a1 = foreground(g, k);
    const double norm = std::hypot(a0, a1);
    if (norm > 0) out[g] = static_cast<float>((a1 - a0) / norm);
  }
  return out;
}

}  // namespace gslift
