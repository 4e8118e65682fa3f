// eval.semantic's protocol (paper 002 §4.2) over a capture with ground-truth semantic maps:
// every predicted view whose capture view has one is scored alone, and the views are pooled into
// one confusion matrix for the training views, one for the held-out views and one for all.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "nodes/eval/semantic_metrics.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/semantic_maps.hpp"
#include "param/param_table.hpp"

namespace gslift {

struct SemanticEvaluation {
  Confusion train, test, all;
  struct ViewScore {
    std::string view;
    bool held_out = false;
    SemanticScores scores;
  };
  std::vector<ViewScore> views;
};

struct SemanticEvalOptions {
  // Pixels a prediction leaves unlabelled (-1: a detector prior covers nothing there) count as
  // background instead of as misses: how the priors alone label a view.
  bool unlabelled_as_background = false;
};

const ParamTable<SemanticEvalOptions>& semantic_eval_param_table();

// Throws InputError when a predicted view is not in the capture, when its size differs from the
// ground truth, or when no predicted view has ground truth.
SemanticEvaluation evaluate_semantics(const SemanticMaps& predictions, const Capture& capture,
                                      const SemanticEvalOptions& options = {});

// One row per class (name, tp, fn, fp, recall, precision in percent, present), then GA, CA, CP.
std::string semantic_class_csv(const SemanticScores& scores, const std::vector<std::string>& names);
// The matrix with a header row of predicted class names (and "unlabelled"), one row per
// ground-truth class.
std::string confusion_csv(const Confusion& confusion, const std::vector<std::string>& names);
// Row-normalised heat map (each cell the fraction of its ground-truth row), `cell` pixels per
// cell, viridis colours, RGB order (write_rgb_png).
cv::Mat confusion_heatmap(const Confusion& confusion, int cell = 24);

// The heat map with its caption strip: what the rows and columns are, the class of each row in
// order, and the colour scale's ends (nodes/scene/caption_strip.hpp).
cv::Mat3b confusion_heatmap_captioned(const Confusion& confusion,
                                      const std::vector<std::string>& classes);

}  // namespace gslift
