#include "nodes/eval/instance_picture.hpp"

#include <set>
#include <vector>

#include "nodes/scene/caption_strip.hpp"
#include "nodes/scene/label_maps.hpp"

namespace gslift {

cv::Mat3b instance_comparison_picture(const cv::Mat1i& truth, const cv::Mat3b& render,
                                      const cv::Mat1i& predicted,
                                      const std::map<int, int>& pred_to_gt,
                                      const std::string& title) {
  if (truth.size() != render.size() || predicted.size() != render.size()) return {};
  const cv::Vec3b unmatched(128, 128, 128);
  const cv::Mat3b gt = label_image(truth);
  cv::Mat3b pred(truth.size(), cv::Vec3b(0, 0, 0));
  std::set<int> matched_shown;
  bool any_unmatched = false;
  for (int y = 0; y < truth.rows; ++y)
    for (int x = 0; x < truth.cols; ++x) {
      const int p = predicted(y, x);
      if (p <= 0) continue;
      const auto it = pred_to_gt.find(p);
      if (it == pred_to_gt.end()) {
        pred(y, x) = unmatched;
        any_unmatched = true;
      } else {
        pred(y, x) = label_colour(it->second);
        matched_shown.insert(it->second);
      }
    }
  std::vector<LegendEntry> legend;
  for (const int id : matched_shown)
    legend.push_back({"instance " + std::to_string(id), label_colour(id)});
  if (any_unmatched) legend.push_back({"unmatched prediction", unmatched});
  return with_caption(side_by_side({{"ground truth", gt}, {"render", render}, {"instances", pred}}),
                      title +
                          ": ground truth | render | instances (coloured as their matched "
                          "ground truth); black: none",
                      legend);
}

}  // namespace gslift
