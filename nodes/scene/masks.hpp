// Instance masks per view: SAM box-prompted masks, SAM automatic masks, or predictions.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "base/port_type.hpp"
#include "nodes/scene/capture.hpp"

namespace gslift {

struct Mask {
  cv::Mat1b pixels;  // full image size, 255 inside, 0 outside
  std::string label;
  float score = 1.f;
  int box_index = -1;   // the box of the view's BoxSet that prompted it, -1 when none
  int granularity = 0;  // SAM automatic masks: 0 whole, 1 part, 2 subpart (SAGA); 0 otherwise
};

struct ViewMasks {
  std::string view;  // view name in the capture
  std::vector<Mask> masks;
};

struct MaskSet {
  std::vector<ViewMasks> views;  // in capture view order
};

GSLIFT_PORT_TYPE(MaskSet, "MaskSet");

// A view of a MaskSet and the capture view it names.
struct MaskView {
  int mask_view = 0;     // index into MaskSet::views
  int capture_view = 0;  // index into Capture::views
};

// The views of `masks` that are training views of `capture`, in MaskSet order: every stage that
// learns from masks (feature training, lifting, association) uses these only, so masks of
// held-out views never leak into what evaluation scores. Throws InputError when a view of `masks`
// (held out or not) is not in the capture, one of its masks differs in size from the view's
// camera, or no training view has masks.
std::vector<MaskView> training_mask_views(const Capture& capture, const MaskSet& masks);

// Intersection over union of two binary masks of one size (nonzero = in); 0 when both are empty.
inline double mask_iou(const cv::Mat1b& a, const cv::Mat1b& b) {
  const int both = cv::countNonZero(a & b);
  if (both == 0) return 0.0;
  return double(both) / (cv::countNonZero(a) + cv::countNonZero(b) - both);
}

}  // namespace gslift
