#include "nodes/inference/label_pieces.hpp"

#include <vector>

namespace gslift {

size_t absorb_small_pieces(cv::Mat1i& labels, int min_pixels) {
  const int w = labels.cols, h = labels.rows;
  if (min_pixels <= 1 || w == 0 || h == 0) return 0;
  if (!labels.isContinuous()) labels = labels.clone();  // the fill below indexes it flat
  const int n = w * h;
  // Flood each 8-connected piece once; `open` marks the pixels of the pieces below min_pixels.
  std::vector<int> piece(n, -1), stack, members;
  std::vector<char> open(n, 0);
  size_t open_pixels = 0;
  for (int start = 0; start < n; ++start) {
    if (piece[start] >= 0) continue;
    const int label = labels(start / w, start % w);
    members.clear();
    stack.assign(1, start);
    piece[start] = start;
    while (!stack.empty()) {
      const int p = stack.back();
      stack.pop_back();
      members.push_back(p);
      const int x = p % w, y = p / w;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int qx = x + dx, qy = y + dy;
          if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
          const int q = qy * w + qx;
          if (piece[q] < 0 && labels(qy, qx) == label) {
            piece[q] = start;
            stack.push_back(q);
          }
        }
    }
    if (static_cast<int>(members.size()) < min_pixels) {
      for (const int p : members) open[p] = 1;
      open_pixels += members.size();
    }
  }
  if (open_pixels == 0 || open_pixels == static_cast<size_t>(n)) return 0;
  // Breadth-first from every kept pixel at once, seeded in raster order.
  std::vector<int> queue;
  queue.reserve(n);
  for (int p = 0; p < n; ++p)
    if (!open[p]) queue.push_back(p);
  int* out = labels.ptr<int>(0);
  for (size_t head = 0; head < queue.size(); ++head) {
    const int p = queue[head];
    const int x = p % w, y = p / w;
    const int neighbours[4][2] = {{x, y - 1}, {x - 1, y}, {x + 1, y}, {x, y + 1}};
    for (const auto& q : neighbours) {
      if (q[0] < 0 || q[1] < 0 || q[0] >= w || q[1] >= h) continue;
      const int i = q[1] * w + q[0];
      if (!open[i]) continue;
      open[i] = 0;
      out[i] = out[p];
      queue.push_back(i);
    }
  }
  return open_pixels;
}

}  // namespace gslift
