#include "nodes/eval/semantic_metrics.hpp"

#include "base/errors.hpp"

namespace gslift {

Confusion& Confusion::operator+=(const Confusion& o) {
  if (o.classes != classes) throw InputError("confusion matrices of different class counts");
  for (size_t i = 0; i < counts.size(); ++i) counts[i] += o.counts[i];
  return *this;
}

void add_to_confusion(const cv::Mat1i& gt, const cv::Mat1i& pred, Confusion& c) {
  if (gt.size() != pred.size())
    throw InputError("semantic evaluation: a " + std::to_string(pred.cols) + "x" +
                     std::to_string(pred.rows) + " prediction for a " + std::to_string(gt.cols) +
                     "x" + std::to_string(gt.rows) + " ground truth");
  for (int y = 0; y < gt.rows; ++y)
    for (int x = 0; x < gt.cols; ++x) {
      const int g = gt(y, x), p = pred(y, x);
      if (g < 0 || g >= c.classes) continue;
      if (p < -1 || p >= c.classes)
        throw InputError("semantic evaluation: predicted class " + std::to_string(p) +
                         " outside 0.." + std::to_string(c.classes - 1));
      ++c.at(g, p < 0 ? c.classes : p);
    }
}

SemanticScores semantic_scores(const Confusion& c) {
  SemanticScores s;
  s.classes.resize(c.classes);
  long long tp_sum = 0;
  int present = 0;
  double recall_sum = 0, precision_sum = 0;
  for (int i = 0; i < c.classes; ++i) {
    SemanticClassScore& k = s.classes[i];
    k.tp = c.at(i, i);
    for (int j = 0; j <= c.classes; ++j)
      if (j != i) k.fn += c.at(i, j);
    for (int g = 0; g < c.classes; ++g)
      if (g != i) k.fp += c.at(g, i);
    k.present = k.tp + k.fn > 0;
    k.recall = k.present ? double(k.tp) / (k.tp + k.fn) : 0.0;
    k.precision = k.tp + k.fp > 0 ? double(k.tp) / (k.tp + k.fp) : 0.0;
    tp_sum += k.tp;
    s.pixels += k.tp + k.fn;
    if (k.present) {
      ++present;
      recall_sum += k.recall;
      precision_sum += k.precision;
    }
  }
  s.ga = s.pixels > 0 ? 100.0 * tp_sum / s.pixels : 0.0;
  s.ca = present > 0 ? 100.0 * recall_sum / present : 0.0;
  s.cp = present > 0 ? 100.0 * precision_sum / present : 0.0;
  return s;
}

}  // namespace gslift
