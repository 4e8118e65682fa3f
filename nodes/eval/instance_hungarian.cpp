#include "nodes/eval/instance_hungarian.hpp"

#include <algorithm>
#include <set>
#include <unordered_map>

#include <Eigen/Core>
#include <opencv2/imgproc.hpp>

#include "base/csv_field.hpp"
#include "base/errors.hpp"
#include "nodes/eval/hungarian.hpp"

namespace gslift {

InstanceScores score_instances_hungarian(const std::vector<cv::Mat1i>& gt,
                                         const std::vector<cv::Mat1i>& pred) {
  if (gt.empty() || gt.size() != pred.size())
    throw InputError("eval.instance_hungarian: one prediction per ground-truth image is needed");
  std::set<int> gt_set, pred_set;
  for (size_t i = 0; i < gt.size(); ++i) {
    if (gt[i].size() != pred[i].size())
      throw InputError("eval.instance_hungarian: image " + std::to_string(i) +
                       ": prediction and ground truth differ in size");
    gt_set.insert(gt[i].begin(), gt[i].end());
    pred_set.insert(pred[i].begin(), pred[i].end());
  }
  InstanceScores s;
  s.gt_ids.assign(gt_set.begin(), gt_set.end());
  const std::vector<int> pred_ids(pred_set.begin(), pred_set.end());
  std::unordered_map<int, int> gi, pi;
  for (size_t k = 0; k < s.gt_ids.size(); ++k) gi[s.gt_ids[k]] = static_cast<int>(k);
  for (size_t k = 0; k < pred_ids.size(); ++k) pi[pred_ids[k]] = static_cast<int>(k);
  const int ng = static_cast<int>(s.gt_ids.size()), np = static_cast<int>(pred_ids.size());

  Eigen::MatrixXd iou_sum = Eigen::MatrixXd::Zero(ng, std::max(ng, np));
  std::vector<int> present(ng, 0);
  for (size_t i = 0; i < gt.size(); ++i) {
    std::unordered_map<int64_t, long> joint;  // key a * np + b
    std::vector<long> ga(ng, 0), pa(np, 0);
    auto g = gt[i].begin();
    for (auto p = pred[i].begin(); p != pred[i].end(); ++p, ++g) {
      const int a = gi[*g], b = pi[*p];
      ++joint[int64_t(a) * np + b];
      ++ga[a];
      ++pa[b];
    }
    for (int a = 0; a < ng; ++a) present[a] += ga[a] > 0;
    for (const auto& [ab, n] : joint) {
      const int a = static_cast<int>(ab / np), b = static_cast<int>(ab % np);
      iou_sum(a, b) += double(n) / (ga[a] + pa[b] - n);
    }
  }
  // Mean over the images where g is present (each pair's images without g added 0 above).
  for (int a = 0; a < ng; ++a) iou_sum.row(a) /= present[a];
  const std::vector<int> match = max_score_assignment(iou_sum);
  for (int a = 0; a < ng; ++a) {
    const int b = match[a];
    const double iou = b >= 0 ? iou_sum(a, b) : 0.0;
    s.matched_pred.push_back(b >= 0 && b < np ? pred_ids[b] : -1);
    s.matched_iou.push_back(iou);
    s.miou += iou / ng;
    s.hits += iou > 0.5;
  }
  s.gt_labels = ng;
  s.pred_labels = np;
  s.precision = double(s.hits) / np;
  s.recall = double(s.hits) / ng;
  return s;
}

InstanceScores score_label_maps(const LabelMapSet& predictions, const Capture& capture) {
  std::vector<cv::Mat1i> gt, pred;
  for (const LabelMap& m : predictions.views) {
    const int v = capture.find_view(m.view);
    if (v < 0 || !capture.views[v].gt_instance.present())
      throw InputError("eval.instance_hungarian: view '" + m.view + "' of capture '" +
                       capture.name + "' has no ground-truth instance map");
    gt.push_back(capture.views[v].gt_instance.load());
    if (m.labels.size() == gt.back().size()) {
      pred.push_back(m.labels);
    } else {
      cv::Mat1i resized;
      cv::resize(m.labels, resized, gt.back().size(), 0, 0, cv::INTER_NEAREST);
      pred.push_back(resized);
    }
  }
  return score_instances_hungarian(gt, pred);
}

std::string instance_matches_csv(const InstanceScores& s, const Capture& capture) {
  std::string csv = "gt_label,class,matched_pred,iou\n";
  for (size_t k = 0; k < s.gt_ids.size(); ++k) {
    std::string name;
    const auto instance = capture.instance_class.find(s.gt_ids[k]);
    if (s.gt_ids[k] != 0 && instance != capture.instance_class.end()) {
      const auto cls = capture.classes.find(instance->second);
      name = cls != capture.classes.end() ? cls->second : std::to_string(instance->second);
    }
    csv += std::to_string(s.gt_ids[k]) + "," + csv_field(name) + "," +
           std::to_string(s.matched_pred[k]) + "," + std::to_string(s.matched_iou[k]) + "\n";
  }
  return csv;
}

}  // namespace gslift
