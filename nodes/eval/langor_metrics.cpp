#include "nodes/eval/langor_metrics.hpp"

#include <map>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace gslift {

MaskCounts compare_masks(const cv::Mat1b& pred, const cv::Mat1b& gt) {
  if (pred.size() != gt.size())
    throw std::invalid_argument("compare_masks: predicted mask " + std::to_string(pred.cols) + "x" +
                                std::to_string(pred.rows) + " vs ground truth " +
                                std::to_string(gt.cols) + "x" + std::to_string(gt.rows));
  MaskCounts c;
  for (int y = 0; y < gt.rows; ++y) {
    const uint8_t* p = pred.ptr<uint8_t>(y);
    const uint8_t* g = gt.ptr<uint8_t>(y);
    for (int x = 0; x < gt.cols; ++x) {
      const bool in_p = p[x] != 0, in_g = g[x] != 0;
      c.intersection += in_p && in_g;
      c.uni += in_p || in_g;
      c.gt += in_g;
      c.pred += in_p;
    }
  }
  return c;
}

double iou(const MaskCounts& c) {
  return c.uni == 0 ? 1.0 : static_cast<double>(c.intersection) / static_cast<double>(c.uni);
}

cv::Point argmax(const cv::Mat1f& map) {
  cv::Point best(0, 0);
  float best_v = map.empty() ? 0.f : map(0, 0);
  for (int y = 0; y < map.rows; ++y)
    for (int x = 0; x < map.cols; ++x)
      if (map(y, x) > best_v) {
        best_v = map(y, x);
        best = {x, y};
      }
  return best;
}

bool localised_in_mask(const cv::Mat1f& relevancy, const cv::Mat1b& gt) {
  if (relevancy.size() != gt.size())
    throw std::invalid_argument("localised_in_mask: relevancy and ground truth differ in size");
  const cv::Point p = argmax(relevancy);
  return gt(p) != 0;
}

bool localised_in_box(const cv::Mat1f& relevancy, const cv::Mat1b& gt, int box) {
  if (relevancy.size() != gt.size())
    throw std::invalid_argument("localised_in_box: relevancy and ground truth differ in size");
  cv::Mat1f smoothed = relevancy;
  if (box > 1)
    cv::blur(relevancy, smoothed, cv::Size(box, box), cv::Point(-1, -1), cv::BORDER_REPLICATE);
  const cv::Rect bounds = cv::boundingRect(gt);
  return bounds.contains(argmax(smoothed));
}

LangorSummary summarise_langor(const std::vector<QueryScore>& scores) {
  LangorSummary s;
  std::map<std::string, size_t> index;
  std::vector<int64_t> inter, gt;
  for (const auto& q : scores) {
    auto [it, added] = index.emplace(q.label, s.classes.size());
    if (added) {
      s.classes.push_back({q.label});
      inter.push_back(0);
      gt.push_back(0);
    }
    ClassScore& c = s.classes[it->second];
    const double i = iou(q.counts);
    ++c.queries;
    c.iou += i;
    c.loc_acc += q.localised;
    c.loc_acc_box += q.localised_box;
    inter[it->second] += q.counts.intersection;
    gt[it->second] += q.counts.gt;
    s.miou += i;
    s.mlocacc += q.localised;
    s.mlocacc_box += q.localised_box;
  }
  s.queries = static_cast<int>(scores.size());
  if (s.queries > 0) {
    s.miou *= 100.0 / s.queries;
    s.mlocacc *= 100.0 / s.queries;
    s.mlocacc_box *= 100.0 / s.queries;
  }
  for (size_t k = 0; k < s.classes.size(); ++k) {
    ClassScore& c = s.classes[k];
    c.iou *= 100.0 / c.queries;
    c.loc_acc *= 100.0 / c.queries;
    c.loc_acc_box *= 100.0 / c.queries;
    c.acc = gt[k] > 0 ? 100.0 * static_cast<double>(inter[k]) / static_cast<double>(gt[k]) : 0.0;
    s.miou_class += c.iou;
    s.macc += c.acc;
  }
  if (!s.classes.empty()) {
    s.miou_class /= static_cast<double>(s.classes.size());
    s.macc /= static_cast<double>(s.classes.size());
  }
  return s;
}

}  // namespace gslift
