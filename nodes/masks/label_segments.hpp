// The segments of a label image as masks: what every automatic mask generator here ends with
// (masks.auto's graph segmentation, masks.geometry's plane and crease regions).
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "nodes/scene/capture.hpp"
#include "nodes/scene/masks.hpp"
#include "param/param_table.hpp"

namespace gslift {

// Which segments an automatic mask generator keeps as masks, and in which views it segments:
// params every generator declares through segment_keep_param_table().
struct SegmentKeep {
  int min_area = 100;  // SAM's min_mask_region_area in SAGA's extraction script
  // Segments covering more than this fraction of the view are dropped (SAGA drops masks with a
  // single value; a segment of almost the whole image says nothing about its parts).
  double max_area_fraction = 0.9;
  ViewSet views = ViewSet::Train;  // test views never need masks: training reads train views
};

const ParamTable<SegmentKeep>& segment_keep_param_table();

// Appends one mask per label id of `labels` (CV_32S; negative = no segment) whose area is in
// [keep.min_area, keep.max_area_fraction x the image's pixels], at `granularity`, in ascending id
// order.
void append_label_segments(const cv::Mat& labels, int granularity, const SegmentKeep& keep,
                           std::vector<Mask>& out);

}  // namespace gslift
