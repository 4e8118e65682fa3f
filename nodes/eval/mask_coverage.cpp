#include "nodes/eval/mask_coverage.hpp"

#include <algorithm>
#include <map>

#include <opencv2/imgproc.hpp>

#include "base/errors.hpp"

namespace gslift {
namespace {

struct MaskArea {
  cv::Rect box;
  int area = 0;
};

MaskArea mask_area(const cv::Mat1b& m) {
  return {cv::boundingRect(m), cv::countNonZero(m)};
}

}  // namespace

std::vector<MaskCoverage> mask_coverage(const MaskSet& masks, const MaskSet& truth) {
  std::map<std::string, const ViewMasks*> predicted;
  for (const ViewMasks& vm : masks.views) predicted[vm.view] = &vm;
  std::map<int, MaskCoverage> rows;  // by granularity, -1 first
  std::map<int, double> sums;
  int views = 0;
  for (const ViewMasks& tv : truth.views) {
    const auto it = predicted.find(tv.view);
    if (it == predicted.end()) continue;
    const std::vector<Mask>& pred = it->second->masks;
    ++views;
    rows[-1].masks_per_view += pred.size();
    std::vector<MaskArea> areas;
    for (const Mask& m : pred) {
      rows[m.granularity].masks_per_view += 1;
      areas.push_back(mask_area(m.pixels));
    }
    for (const Mask& t : tv.masks) {
      const MaskArea ta = mask_area(t.pixels);
      std::map<int, double> best;  // granularity -> best IoU
      for (size_t k = 0; k < pred.size(); ++k) {
        if (pred[k].pixels.size() != t.pixels.size())
          throw InputError("mask coverage: view '" + tv.view + "' has a mask of " +
                           std::to_string(pred[k].pixels.cols) + "x" +
                           std::to_string(pred[k].pixels.rows) + " against its truth's " +
                           std::to_string(t.pixels.cols) + "x" + std::to_string(t.pixels.rows));
        // Only the overlap of the two boxes can hold pixels of both.
        const cv::Rect both = ta.box & areas[k].box;
        double iou = 0;
        if (both.area() > 0) {
          const int inter = cv::countNonZero(t.pixels(both) & pred[k].pixels(both));
          iou = inter > 0 ? double(inter) / (ta.area + areas[k].area - inter) : 0.0;
        }
        double& b = best[pred[k].granularity];
        b = std::max(b, iou);
      }
      double any = 0;
      for (const auto& [g, iou] : best) any = std::max(any, iou);
      sums[-1] += any;
      ++rows[-1].instances;
      for (auto& [g, row] : rows) {
        if (g < 0) continue;
        sums[g] += best.count(g) ? best[g] : 0.0;
      }
    }
  }
  if (views == 0) throw InputError("mask coverage: the masks and the ground truth share no view");
  if (rows[-1].instances == 0)
    throw InputError(
        "mask coverage: the views the masks and the truth share have no "
        "ground-truth mask");
  std::vector<MaskCoverage> out;
  for (auto& [g, row] : rows) {
    row.granularity = g;
    row.instances = rows[-1].instances;
    row.mean_best_iou = 100.0 * sums[g] / row.instances;
    row.masks_per_view /= views;
    out.push_back(row);
  }
  return out;
}

}  // namespace gslift
