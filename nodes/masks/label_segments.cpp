#include "nodes/masks/label_segments.hpp"

namespace gslift {

const ParamTable<SegmentKeep>& segment_keep_param_table() {
  using O = SegmentKeep;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("min_area", &O::min_area, "smallest segment kept as a mask, pixels", 1, 1e8)
          .add("max_area_fraction", &O::max_area_fraction,
               "segments covering more of the view are dropped", 0, 1)
          .add("views", &O::views, view_set_names(), "views to segment");
  return table;
}

void append_label_segments(const cv::Mat& labels, int granularity, const SegmentKeep& keep,
                           std::vector<Mask>& out) {
  CV_Assert(labels.type() == CV_32S);
  const int min_area = keep.min_area;
  const int max_area = static_cast<int>(keep.max_area_fraction * labels.total());
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
