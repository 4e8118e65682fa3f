#include "nodes/inference/label_argmax.hpp"

#include <tbb/parallel_for.h>

#include "base/errors.hpp"

namespace gslift {

cv::Mat1i argmax_labels(const std::vector<float>& scores, int width, int height,
                        const std::vector<int>& ids) {
  const size_t n = ids.size(), pixels = size_t(width) * height;
  if (n == 0 || scores.size() != pixels * n)
    throw InputError("inference: the label scores do not match the view and the candidates");
  cv::Mat1i out(height, width);
  tbb::parallel_for(size_t(0), pixels, [&](size_t p) {
    const float* s = scores.data() + p * n;
    size_t best = 0;
    for (size_t c = 1; c < n; ++c)
      if (s[c] > s[best]) best = c;
    out(static_cast<int>(p / width), static_cast<int>(p % width)) = ids[best];
  });
  return out;
}

}  // namespace gslift
