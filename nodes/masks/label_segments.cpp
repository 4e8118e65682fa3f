#include "nodes/masks/label_segments.hpp"

namespace gslift {

void append_label_segments(const cv::Mat& labels, int granularity, int min_area, int max_area,
                           std::vector<Mask>& out) {
  CV_Assert(labels.type() == CV_32S);
  double top = -1;
  cv::minMaxLoc(labels, nullptr, &top);
  if (top < 0) return;
  std::vector<int> area(static_cast<size_t>(top) + 1, 0);
  for (auto it = labels.begin<int32_t>(); it != labels.end<int32_t>(); ++it)
    if (*it >= 0) ++area[*it];
  for (size_t id = 0; id < area.size(); ++id) {
    if (area[id] < min_area || area[id] > max_area) continue;
    Mask m;
    m.pixels = labels == static_cast<int>(id);
    m.granularity = granularity;
    out.push_back(std::move(m));
  }
}

}  // namespace gslift
