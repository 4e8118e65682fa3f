#include "nodes/inference/label_argmax.hpp"

#include <algorithm>

#include <tbb/parallel_for.h>

#include "base/errors.hpp"

namespace gslift {
namespace {

// argmax over the candidates with allowed[c] (all when empty); ties keep the lower candidate.
int best_candidate(const float* s, size_t candidates, const std::vector<char>& allowed) {
  int best = -1;
  for (size_t c = 0; c < candidates; ++c)
    if ((allowed.empty() || allowed[c]) && (best < 0 || s[c] > s[best])) best = static_cast<int>(c);
  return best;
}

}  // namespace

cv::Mat1i argmax_labels(const std::vector<float>& scores, int width, int height,
                        const std::vector<int>& ids, double min_area) {
  const size_t n = ids.size(), pixels = size_t(width) * height;
  if (n == 0 || scores.size() != pixels * n)
    throw InputError("inference: the label scores do not match the view and the candidates");
  std::vector<int> best(pixels);
  tbb::parallel_for(size_t(0), pixels,
                    [&](size_t p) { best[p] = best_candidate(scores.data() + p * n, n, {}); });
  if (min_area > 0) {
    std::vector<size_t> area(n, 0);
    for (const int b : best) ++area[b];
    const size_t largest = std::max_element(area.begin(), area.end()) - area.begin();
    std::vector<char> allowed(n);
    bool dropped = false;
    for (size_t c = 0; c < n; ++c) {
      allowed[c] = c == largest || area[c] >= min_area * pixels;
      dropped |= area[c] > 0 && !allowed[c];
    }
    if (dropped)
      tbb::parallel_for(size_t(0), pixels, [&](size_t p) {
        if (!allowed[best[p]]) best[p] = best_candidate(scores.data() + p * n, n, allowed);
      });
  }
  cv::Mat1i out(height, width);
  for (size_t p = 0; p < pixels; ++p)
    out(static_cast<int>(p / width), static_cast<int>(p % width)) = ids[best[p]];
  return out;
}

}  // namespace gslift
