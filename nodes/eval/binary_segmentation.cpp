#include "nodes/eval/binary_segmentation.hpp"

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>

#include "base/errors.hpp"

namespace gslift {

BinaryCounts binary_counts(const cv::Mat1b& pred, const cv::Mat1b& truth) {
  if (pred.size() != truth.size())
    throw InputError("eval.binary_segmentation: a predicted mask is " + std::to_string(pred.cols) +
                     "x" + std::to_string(pred.rows) + ", its ground truth " +
                     std::to_string(truth.cols) + "x" + std::to_string(truth.rows));
  BinaryCounts c;
  for (int y = 0; y < pred.rows; ++y) {
    const uint8_t* p = pred.ptr<uint8_t>(y);
    const uint8_t* t = truth.ptr<uint8_t>(y);
    for (int x = 0; x < pred.cols; ++x) {
      const bool a = p[x] != 0, b = t[x] != 0;
      (a ? (b ? c.tp : c.fp) : (b ? c.fn : c.tn)) += 1;
    }
  }
  return c;
}

double binary_iou(const BinaryCounts& c) {
  const int64_t u = c.tp + c.fp + c.fn;
  return u == 0 ? 1.0 : double(c.tp) / double(u);
}

double binary_accuracy(const BinaryCounts& c) {
  const int64_t all = c.tp + c.fp + c.fn + c.tn;
  return all == 0 ? 1.0 : double(c.tp + c.tn) / double(all);
}

double binary_precision(const BinaryCounts& c) {
  return c.tp + c.fp == 0 ? 1.0 : double(c.tp) / double(c.tp + c.fp);
}

double binary_recall(const BinaryCounts& c) {
  return c.tp + c.fn == 0 ? 1.0 : double(c.tp) / double(c.tp + c.fn);
}

BinarySegmentationSummary score_binary_segmentation(const MaskSet& predictions,
                                                    const MaskSet& truth,
                                                    const BinarySegmentationOptions& o) {
  std::map<std::string, const ViewMasks*> truth_views;
  std::set<std::string> truth_labels;
  for (const ViewMasks& v : truth.views) {
    truth_views[v.view] = &v;
    for (const Mask& m : v.masks) truth_labels.insert(m.label);
  }
  const std::set<std::string> excluded(o.exclude_views.begin(), o.exclude_views.end());
  BinarySegmentationSummary s;
  std::map<std::string, size_t> label_index;
  for (const ViewMasks& pv : predictions.views) {
    const auto tv = truth_views.find(pv.view);
    if (tv == truth_views.end() || excluded.count(pv.view)) continue;
    for (const Mask& pm : pv.masks) {
      if (!truth_labels.count(pm.label))
        throw InputError("eval.binary_segmentation: the prediction '" + pm.label +
                         "' names no ground-truth mask of any view");
      const Mask* gt = nullptr;
      for (const Mask& tm : tv->second->masks)
        if (tm.label == pm.label) gt = &tm;
      if (!gt) continue;  // the object is not in this view: not a target view for it
      BinaryViewScore v{pm.label, pv.view, binary_counts(pm.pixels, gt->pixels)};
      v.iou = binary_iou(v.counts);
      v.accuracy = binary_accuracy(v.counts);
      v.precision = binary_precision(v.counts);
      v.recall = binary_recall(v.counts);
      auto [it, added] = label_index.emplace(pm.label, s.labels.size());
      if (added) s.labels.push_back({pm.label});
      BinaryLabelScore& l = s.labels[it->second];
      ++l.views;
      l.iou += v.iou;
      l.accuracy += v.accuracy;
      l.precision += v.precision;
      l.recall += v.recall;
      s.views.push_back(std::move(v));
    }
  }
  for (BinaryLabelScore& l : s.labels) {
    l.iou *= 100.0 / l.views;
    l.accuracy *= 100.0 / l.views;
    l.precision *= 100.0 / l.views;
    l.recall *= 100.0 / l.views;
    s.miou += l.iou / s.labels.size();
    s.macc += l.accuracy / s.labels.size();
    s.mprecision += l.precision / s.labels.size();
    s.mrecall += l.recall / s.labels.size();
  }
  return s;
}

std::string binary_segmentation_markdown(const BinarySegmentationSummary& s) {
  std::string out =
      "| prompt | views | IoU | Acc | precision | recall |\n| --- | ---: | ---: | ---: | ---: | "
      "---: "
      "|\n";
  char line[256];
  for (const BinaryLabelScore& l : s.labels) {
    std::snprintf(line, sizeof line, "| %s | %d | %.1f | %.1f | %.1f | %.1f |\n", l.label.c_str(),
                  l.views, l.iou, l.accuracy, l.precision, l.recall);
    out += line;
  }
  std::snprintf(line, sizeof line, "| **mean** | | **%.1f** | **%.1f** | %.1f | %.1f |\n", s.miou,
                s.macc, s.mprecision, s.mrecall);
  return out + line;
}

std::string binary_segmentation_csv(const BinarySegmentationSummary& s) {
  std::string out = "prompt,view,tp,fp,fn,tn,iou,accuracy\n";
  char line[512];
  for (const BinaryViewScore& v : s.views) {
    std::snprintf(line, sizeof line, "%s,%s,%lld,%lld,%lld,%lld,%.6f,%.6f\n", v.label.c_str(),
                  v.view.c_str(), static_cast<long long>(v.counts.tp),
                  static_cast<long long>(v.counts.fp), static_cast<long long>(v.counts.fn),
                  static_cast<long long>(v.counts.tn), v.iou, v.accuracy);
    out += line;
  }
  return out;
}

const ParamTable<BinarySegmentationOptions>& binary_segmentation_param_table() {
  using O = BinarySegmentationOptions;
  static const ParamTable<O> table =
      ParamTable<O>().add("exclude_views", &O::exclude_views,
                          "views never scored (e.g. the view the prompt was given in)");
  return table;
}

}  // namespace gslift
