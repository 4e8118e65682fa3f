#include "nodes/association/sam_partition.hpp"

#include <algorithm>
#include <numeric>
#include <vector>

namespace gslift {

cv::Mat1i sam_partition(const ViewMasks& masks, int granularity, cv::Size size,
                        double min_visible) {
  std::vector<int> order;
  for (size_t k = 0; k < masks.masks.size(); ++k)
    if (masks.masks[k].granularity == granularity) order.push_back(static_cast<int>(k));
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return masks.masks[a].score < masks.masks[b].score; });
  // Paint 1-based positions in `order`, then count what stays visible of each.
  cv::Mat1i painted = cv::Mat1i::zeros(size);
  std::vector<int> area(order.size() + 1, 0), visible(order.size() + 1, 0);
  for (size_t k = 0; k < order.size(); ++k) {
    const cv::Mat1b& m = masks.masks[order[k]].pixels;
    area[k + 1] = cv::countNonZero(m);
    painted.setTo(static_cast<int>(k + 1), m);
  }
  for (const int id : painted) ++visible[id];
  std::vector<int> renumber(order.size() + 1, 0);
  int next = 0;
  for (size_t k = 1; k <= order.size(); ++k)
    if (area[k] > 0 && visible[k] > min_visible * area[k]) renumber[k] = ++next;
  for (int& id : painted) id = renumber[id];
  return painted;
}

}  // namespace gslift
