// SAM outputs as masks: automatic-mask-generator JSON, box-prompted mask lists, and 16-bit
// instance-id maps.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "nodes/scene/masks.hpp"

namespace gslift {

// SAM automatic masks: a JSON list of records {segmentation: COCO RLE, bbox: [x, y, w, h], area,
// predicted_iou, stability_score, granularity?}. Mask::score = predicted_iou (1 when absent),
// Mask::granularity = granularity (0 when absent). Masks have the RLE's size. Errors throw
// InputError starting with `where`.
std::vector<Mask> parse_sam_auto_masks(const std::string& json_text, const std::string& where);

// The record SAM's generator writes for one mask: COCO RLE segmentation (compressed counts, as
// SAM's "coco_rle" output mode writes them), bbox, area, predicted_iou and stability_score. The
// inverse of one entry of parse_sam_auto_masks (a caller adds "granularity" when it has one).
nlohmann::json sam_mask_record(const cv::Mat1b& mask, double predicted_iou, double stability);

// Box-prompted SAM masks of one VLM round: a JSON list aligned with the reply's boxes, each entry
// a COCO RLE, a record {segmentation: RLE, score | predicted_iou}, or null for "no mask".
std::vector<std::optional<Mask>> parse_sam_box_masks(const std::string& json_text,
                                                     const std::string& where);

// One mask per nonzero id of a CV_32SC1 instance map, in ascending id order; Mask::label holds
// the id in decimal (e.g. "12").
std::vector<Mask> masks_from_instance_map(const cv::Mat& ids);

}  // namespace gslift
