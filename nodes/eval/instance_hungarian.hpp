// Gaga's eval.py (method-anchors §3.1, METHODS.md §2.4), to the letter: class-agnostic instance
// segmentation scored by a one-to-one Hungarian matching of predicted to ground-truth labels.
//  - Label sets: every id present in some test image, for the ground truth and for the
//    prediction, label 0 included on both sides.
//  - IoU(g, p) = mean over the images where g is present of |G_i n P_i| / |G_i u P_i| (an image
//    where p is absent counts 0), from one joint histogram per image:
//    IoU_i = n_gp / (a_g + a_p - n_gp), O(pixels) per image instead of Gaga's per-pair loops.
//  - linear_sum_assignment(maximize) on [num_gt x max(num_gt, num_pred)], zero-padded.
//  - mIoU = mean over GT labels of the matched IoU; hit = matched IoU > 0.5 (strict);
//    precision = hits / #pred labels, recall = hits / #GT labels.
// Parts against whole instances: a SAM part label (e.g. a person's head) can match at most one
// GT instance and covers only part of it, so splits lower the matched IoU and add unmatched
// predicted labels (precision), exactly as Gaga's Replica protocol scores them.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "nodes/scene/capture.hpp"
#include "nodes/scene/label_maps.hpp"

namespace gslift {

struct InstanceScores {
  double miou = 0, precision = 0, recall = 0;
  int gt_labels = 0, pred_labels = 0, hits = 0;
  std::vector<int> gt_ids;        // ascending
  std::vector<int> matched_pred;  // per GT label: the predicted id matched, -1 for padding
  std::vector<double> matched_iou;
};

// gt[i] and pred[i]: CV_32SC1 maps of one image (same size; the caller resizes the prediction
// nearest-neighbour as Gaga does). Throws InputError on a size mismatch or no images.
InstanceScores score_instances_hungarian(const std::vector<cv::Mat1i>& gt,
                                         const std::vector<cv::Mat1i>& pred);

// The predicted maps of `predictions` against the ground-truth instance maps of the views they
// name (any views: held-out ones end to end, training ones to score the association alone).
// Predictions of another size are resized nearest-neighbour (Gaga). Throws InputError when a
// view is missing from the capture or has no ground-truth instance map.
InstanceScores score_label_maps(const LabelMapSet& predictions, const Capture& capture);

// matches.csv: per ground-truth label, `gt_label,class,matched_pred,iou`, with the class name the
// capture gives the instance (Capture::instance_class, classes), empty for label 0 and for an
// instance without one, so results can be broken down per class across runs.
std::string instance_matches_csv(const InstanceScores& s, const Capture& capture);

}  // namespace gslift
