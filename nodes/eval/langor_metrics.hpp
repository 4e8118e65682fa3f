// The LangOR / LangSplat open-vocabulary segmentation metrics, as plain functions
// over binary masks (255 = in) and relevancy maps, so each can be checked by hand.
//  - IoU of the predicted vs the ground-truth mask of one (view, class) query;
//  - localisation: does the highest-relevancy pixel fall inside the ground truth? Two variants:
//    plain argmax inside the GT mask (the one eval.langor reports as mLocAcc), and
//    LangSplat's: relevancy smoothed by a box filter (30 x 30 in LangSplat), argmax inside the GT
//    mask's bounding box (reported as mLocAcc_box);
//  - accuracy |GT ∩ Pred| / |GT|, pooled per class over its queries, averaged over classes (mAcc).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace gslift {

struct MaskCounts {
  int64_t intersection = 0;  // |GT ∩ Pred|
  int64_t uni = 0;           // |GT ∪ Pred|
  int64_t gt = 0;            // |GT|
  int64_t pred = 0;          // |Pred|
};

// Pixel counts of two same-sized masks (non-zero = in). Throws std::invalid_argument on a size
// mismatch.
MaskCounts compare_masks(const cv::Mat1b& pred, const cv::Mat1b& gt);
// |GT ∩ Pred| / |GT ∪ Pred|; 1 when both are empty (nothing to find, nothing found).
double iou(const MaskCounts& c);

// The first (row-major) pixel of maximal value.
cv::Point argmax(const cv::Mat1f& map);
// True when the argmax of `relevancy` lies inside `gt`.
bool localised_in_mask(const cv::Mat1f& relevancy, const cv::Mat1b& gt);
// LangSplat's variant: argmax of the `box` x `box` mean-filtered relevancy (border replicated)
// inside the bounding box of `gt`. box <= 1 skips the filter.
bool localised_in_box(const cv::Mat1f& relevancy, const cv::Mat1b& gt, int box);

// One evaluated (view, class) query.
struct QueryScore {
  std::string view;
  std::string label;
  MaskCounts counts;
  bool localised = false;      // localised_in_mask
  bool localised_box = false;  // localised_in_box
};

struct ClassScore {
  std::string label;
  int queries = 0;         // test views where the class is present
  double iou = 0;          // mean IoU over its queries
  double loc_acc = 0;      // fraction localised (mask variant)
  double loc_acc_box = 0;  // fraction localised (box variant)
  double acc = 0;          // sum |GT ∩ Pred| / sum |GT| over its queries
};

// Every number in percent, as the papers report them.
struct LangorSummary {
  std::vector<ClassScore> classes;  // in order of first appearance among the queries
  int queries = 0;
  double miou = 0;         // mean IoU over all (view, class) queries (LangSplat)
  double miou_class = 0;   // mean over classes of their mean IoU
  double mlocacc = 0;      // over all queries, mask variant (reported)
  double mlocacc_box = 0;  // over all queries, LangSplat box-filter variant
  double macc = 0;         // (1/K) sum_i |GT_i ∩ Pred_i| / |GT_i| over the K classes
};

LangorSummary summarise_langor(const std::vector<QueryScore>& scores);

}  // namespace gslift
