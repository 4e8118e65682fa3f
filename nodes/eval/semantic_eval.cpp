#include "nodes/eval/semantic_eval.hpp"

#include <cstdio>

#include <opencv2/imgproc.hpp>

#include "base/csv_field.hpp"
#include "base/errors.hpp"
#include "base/fixed_point.hpp"
#include "nodes/scene/caption_strip.hpp"

namespace gslift {

SemanticEvaluation evaluate_semantics(const SemanticMaps& predictions, const Capture& capture,
                                      const SemanticEvalOptions& options) {
  const int c = predictions.class_count();
  SemanticEvaluation e{Confusion(c), Confusion(c), Confusion(c), {}};
  for (const SemanticView& pv : predictions.views) {
    const int vi = capture.find_view(pv.view);
    if (vi < 0)
      throw InputError("eval.semantic: predictions name view '" + pv.view + "' that the capture '" +
                       capture.name + "' lacks");
    const View& view = capture.views[vi];
    if (!view.gt_semantic.present()) continue;
    const cv::Mat gt = view.gt_semantic.load();
    Confusion one(c);
    cv::Mat1i labels = pv.labels;
    if (options.unlabelled_as_background) {
      labels = pv.labels.clone();
      labels.setTo(0, pv.labels == -1);
    }
    add_to_confusion(gt, labels, one);
    (view.held_out ? e.test : e.train) += one;
    e.all += one;
    e.views.push_back({pv.view, view.held_out, semantic_scores(one)});
  }
  if (e.views.empty())
    throw InputError("eval.semantic: no predicted view of capture '" + capture.name +
                     "' has a ground-truth semantic map (gt/semantic)");
  return e;
}

std::string semantic_class_csv(const SemanticScores& s, const std::vector<std::string>& names) {
  std::string out = "class,tp,fn,fp,recall,precision,present\n";
  for (size_t i = 0; i < s.classes.size(); ++i) {
    const SemanticClassScore& k = s.classes[i];
    out += csv_field(i < names.size() ? names[i] : std::to_string(i)) + "," + std::to_string(k.tp) +
           "," + std::to_string(k.fn) + "," + std::to_string(k.fp) + "," + fixed2(100 * k.recall) +
           "," + fixed2(100 * k.precision) + "," + (k.present ? "1" : "0") + "\n";
  }
  out +=
      "GA,,,,," + fixed2(s.ga) + ",\nCA,,,,," + fixed2(s.ca) + ",\nCP,,,,," + fixed2(s.cp) + ",\n";
  return out;
}

std::string confusion_csv(const Confusion& m, const std::vector<std::string>& names) {
  auto name = [&](int i) {
    return csv_field(i < int(names.size()) ? names[i] : std::to_string(i));
  };
  std::string out = "ground truth \\ predicted";
  for (int j = 0; j < m.classes; ++j) out += "," + name(j);
  out += ",unlabelled\n";
  for (int i = 0; i < m.classes; ++i) {
    out += name(i);
    for (int j = 0; j <= m.classes; ++j) out += "," + std::to_string(m.at(i, j));
    out += "\n";
  }
  return out;
}

cv::Mat confusion_heatmap(const Confusion& m, int cell) {
  cv::Mat1b grey(m.classes, m.classes + 1, uchar(0));
  for (int i = 0; i < m.classes; ++i) {
    long long row = 0;
    for (int j = 0; j <= m.classes; ++j) row += m.at(i, j);
    if (row == 0) continue;
    for (int j = 0; j <= m.classes; ++j)
      grey(i, j) = cv::saturate_cast<uchar>(255.0 * m.at(i, j) / row);
  }
  cv::Mat1b big;
  cv::resize(grey, big, {grey.cols * cell, grey.rows * cell}, 0, 0, cv::INTER_NEAREST);
  cv::Mat bgr, rgb;
  cv::applyColorMap(big, bgr, cv::COLORMAP_VIRIDIS);
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  return rgb;
}

cv::Mat3b confusion_heatmap_captioned(const Confusion& m, const std::vector<std::string>& classes) {
  // The colour scale's ends and middle, from the same colour map as the cells.
  cv::Mat1b shares(1, 3);
  shares << 0, 128, 255;
  cv::Mat bgr;
  cv::applyColorMap(shares, bgr, cv::COLORMAP_VIRIDIS);
  std::vector<LegendEntry> legend;
  const char* names[] = {"0% of the row", "50%", "100%"};
  for (int k = 0; k < 3; ++k) {
    const cv::Vec3b c = bgr.at<cv::Vec3b>(0, k);
    legend.push_back({names[k], cv::Vec3b(c[2], c[1], c[0])});
  }
  // The rows' (and columns') classes in order, on white swatches: names, not colours.
  for (size_t i = 0; i < classes.size(); ++i)
    legend.push_back({std::to_string(i) + " " + classes[i], cv::Vec3b(255, 255, 255)});
  return with_caption(confusion_heatmap(m),
                      "confusion: rows ground truth, columns predicted (last: unlabelled)", legend);
}

const ParamTable<SemanticEvalOptions>& semantic_eval_param_table() {
  using O = SemanticEvalOptions;
  static const ParamTable<O> table = ParamTable<O>().add(
      "unlabelled_as_background", &O::unlabelled_as_background,
      "pixels left unlabelled (-1) count as background (class 0) instead of as misses");
  return table;
}

}  // namespace gslift
