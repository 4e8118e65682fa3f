// Binary foreground segmentation scores of promptable segmentation, as NVOS / SPIn-NeRF report
// them for SA3D and SAGA (paper 001 §5; the SA3D maintainer's definition,
// Jumpat/SegmentAnythingin3D #20): per target view, IoU = TP / (TP + FP + FN) and accuracy = (TP +
// TN) / all pixels of the predicted vs the ground-truth mask; a prompt's score is the mean over its
// target views, and the table's score the mean over prompts (one object per scene in NVOS: the mean
// over scenes).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "nodes/scene/masks.hpp"
#include "param/param_table.hpp"

namespace gslift {

struct BinaryCounts {
  int64_t tp = 0, fp = 0, fn = 0, tn = 0;
};

// Pixel counts of a predicted vs a ground-truth mask of one size (non-zero = in). Throws
// InputError on a size mismatch.
BinaryCounts binary_counts(const cv::Mat1b& pred, const cv::Mat1b& truth);
// TP / (TP + FP + FN); 1 when both masks are empty (nothing to find, nothing found).
double binary_iou(const BinaryCounts& c);
// (TP + TN) / all pixels; 1 for an empty image.
double binary_accuracy(const BinaryCounts& c);
// How much of a selection is the object, TP / (TP + FP), and how much of the object it holds,
// TP / (TP + FN): what IoU mixes, apart (over- against under-selection). Precision is 1 for an
// empty prediction (nothing wrong selected: its recall says what it missed), recall 1 when there
// is nothing to find.
double binary_precision(const BinaryCounts& c);
double binary_recall(const BinaryCounts& c);

struct BinarySegmentationOptions {
  // Views never scored (e.g. the view the prompt was given in, where the prompt itself is the
  // answer's source).
  std::vector<std::string> exclude_views;
};
const ParamTable<BinarySegmentationOptions>& binary_segmentation_param_table();

struct BinaryViewScore {
  std::string label;  // the prompt (mask label)
  std::string view;
  BinaryCounts counts;
  double iou = 0, accuracy = 0, precision = 0, recall = 0;
};

struct BinaryLabelScore {
  std::string label;
  int views = 0;                                            // target views scored
  double iou = 0, accuracy = 0, precision = 0, recall = 0;  // means over those views, percent
};

struct BinarySegmentationSummary {
  std::vector<BinaryViewScore> views;    // every scored (label, view)
  std::vector<BinaryLabelScore> labels;  // in order of first appearance among the predictions
  double miou = 0, macc = 0, mprecision = 0, mrecall = 0;  // means over labels, percent
};

// Scores every predicted mask of a view that `truth` also has (truth views without a
// prediction, and predicted views without truth, are not target views). The ground truth of a
// prediction is the truth mask of the same view with the same label; a view whose truth lacks
// that label does not show the object and is no target view for it (NVOS and SPIn-NeRF score
// views that show the object). A label found in no truth view at all is an InputError, as are
// size mismatches.
BinarySegmentationSummary score_binary_segmentation(const MaskSet& predictions,
                                                    const MaskSet& truth,
                                                    const BinarySegmentationOptions& options);

// The summary as a Markdown table (one row per label, then the mean) and as CSV rows.
std::string binary_segmentation_markdown(const BinarySegmentationSummary& s);
std::string binary_segmentation_csv(const BinarySegmentationSummary& s);

}  // namespace gslift
