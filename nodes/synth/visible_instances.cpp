#include "nodes/synth/visible_instances.hpp"

#include <algorithm>

namespace gslift::synth {

std::vector<VisibleInstance> visible_instances(const cv::Mat& instance_map,
                                               const std::map<int, int>& instance_class,
                                               double min_fraction) {
  std::map<int, VisibleInstance> found;
  for (int y = 0; y < instance_map.rows; ++y) {
    const int* row = instance_map.ptr<int>(y);
    for (int x = 0; x < instance_map.cols; ++x) {
      if (row[x] == 0) continue;
      auto [it, fresh] = found.try_emplace(row[x]);
      VisibleInstance& v = it->second;
      if (fresh) {
        v.instance = row[x];
        v.box.x1 = static_cast<float>(x), v.box.y1 = static_cast<float>(y);
        v.box.x2 = static_cast<float>(x + 1), v.box.y2 = static_cast<float>(y + 1);
      }
      ++v.pixels;
      v.box.x1 = std::min(v.box.x1, static_cast<float>(x));
      v.box.y1 = std::min(v.box.y1, static_cast<float>(y));
      v.box.x2 = std::max(v.box.x2, static_cast<float>(x + 1));
      v.box.y2 = std::max(v.box.y2, static_cast<float>(y + 1));
    }
  }
  const double min_pixels = min_fraction * instance_map.rows * instance_map.cols;
  std::vector<VisibleInstance> out;
  for (auto& [id, v] : found) {
    if (v.pixels < min_pixels) continue;
    auto cls = instance_class.find(id);
    v.class_id = cls == instance_class.end() ? 0 : cls->second;
    out.push_back(v);
  }
  return out;
}

}  // namespace gslift::synth
