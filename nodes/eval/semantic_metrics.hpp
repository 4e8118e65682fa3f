// Semantic segmentation metrics of paper 002 §4.2 from a confusion matrix:
//   GA = sum_i tp_i / sum_i (tp_i + fn_i)       (global pixel accuracy)
//   CA = 1/n sum_i tp_i / (tp_i + fn_i)         (mean class recall)
//   CP = 1/n sum_i tp_i / (tp_i + fp_i)         (mean class precision)
// (the paper prints CA and CP with the sums outside the fraction; its text, "average class
// recall / precision", and the NYUv2 numbers are the per-class means). n counts the classes with
// ground-truth pixels in the evaluated views [decision: a class no view shows has no recall]; a
// present class that is never predicted has precision 0.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace gslift {

// counts[gt][pred]: rows the ground-truth classes 0..C-1, columns the predicted classes 0..C-1
// and a last column for pixels the prediction leaves unlabelled (-1: a miss, never a false
// positive of any class).
struct Confusion {
  int classes = 0;
  std::vector<long long> counts;  // C x (C + 1), row-major

  explicit Confusion(int c = 0) : classes(c), counts(size_t(c) * (c + 1), 0) {}
  long long& at(int gt, int pred) { return counts[size_t(gt) * (classes + 1) + pred]; }
  long long at(int gt, int pred) const { return counts[size_t(gt) * (classes + 1) + pred]; }
  Confusion& operator+=(const Confusion& o);
};

// Adds every pixel whose ground truth is a class 0..C-1 (others are not evaluated). prediction
// -1 goes to the unlabelled column; a predicted class outside 0..C-1 throws InputError.
void add_to_confusion(const cv::Mat1i& ground_truth, const cv::Mat1i& prediction,
                      Confusion& confusion);

struct SemanticClassScore {
  long long tp = 0, fn = 0, fp = 0;
  double recall = 0, precision = 0;  // 0 when undefined
  bool present = false;              // tp + fn > 0
};

struct SemanticScores {
  double ga = 0, ca = 0, cp = 0;  // in percent
  std::vector<SemanticClassScore> classes;
  long long pixels = 0;  // evaluated ground-truth pixels
};

SemanticScores semantic_scores(const Confusion& confusion);

}  // namespace gslift
