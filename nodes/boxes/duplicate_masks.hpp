// Box-prompted masks that are another box's object (issue 11, docs/langor.md "Where the classes
// are lost" 2). A box-prompted segmenter returns the most salient object inside the box: for the
// box of a mostly hidden support (the operating table under the patient, with surgeons at it) it
// returns the patient or a surgeon, whose own box then has (nearly) the same mask. Two masks of a
// view with different labels and mask IoU >= iou are one object; it belongs to the box whose
// rectangle fits the mask's bounding rectangle best, and the other box's mask is a duplicate.
// [decision] gslift addition, not in LangOR (which keeps SAM's masks as they are, repair =
// keep): a duplicate puts the table's label into the person's instance at association and gives
// the table no pixels of its own. drop removes it; regrow replaces it with GrabCut of its box on
// RGB and depth with every other mask of the view as definite background (grabcut_box_mask), the
// part of the box that is none of the objects the view's other boxes found.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "nodes/scene/boxes.hpp"
#include "nodes/scene/masks.hpp"
#include "param/param_table.hpp"

namespace gslift {

struct GrabCutOptions;  // box_masks.hpp, which nests these options in boxes.to_masks'

enum class DuplicateRepair { Keep, Drop, Regrow };
const EnumNames<DuplicateRepair>& duplicate_repair_names();  // keep, drop, regrow

struct DuplicateMaskOptions {
  DuplicateRepair repair = DuplicateRepair::Keep;  // keep: LangOR's masks as SAM gave them
  float iou = 0.8f;  // two differently labelled masks at least this similar are one object
  // [decision] The mask is another box's object only when that box fits it clearly better: its
  // box_fit times this ratio still above the mask's own box's. Two boxes that fit one object
  // about equally are one object named twice by the VLM (seed 2: a "circulating nurse" box fits
  // the assistant surgeon's mask 0.82 against 0.88), and the mask is right for both; the label
  // vote at association settles it. The hidden tables' boxes fit the person's mask at most 0.81 x
  // as well as the person's box (embedded OR, seeds 0-4). 1: any better fit.
  float fit_ratio = 0.85f;
  // A regrown mask smaller than this (pixels) is dropped: the box shows too little of its
  // object beside the others to learn it from.
  int min_pixels = 100;
};

// Its params: duplicates, duplicate_iou, duplicate_fit_ratio, duplicate_min_pixels.
const ParamTable<DuplicateMaskOptions>& duplicate_mask_param_table();

// How well a mask fits a box: IoU of the box with the mask's bounding rectangle (pixel-corner
// convention); 0 for an empty mask.
double box_fit(const Box& box, const cv::Mat1b& mask);

// For masks[i] (nonzero = in, one per box, same order): the index of the mask it duplicates, or
// -1. masks[i] duplicates masks[j] when their labels differ, mask_iou >= iou and box i fits the
// mask less than fit_ratio times as well as box j does (box_fit of masks[j]; at ratio 1 a tie
// keeps both). The owner j is the best fitting box among all that i duplicates.
std::vector<int> find_duplicate_masks(const std::vector<Box>& boxes,
                                      const std::vector<cv::Mat1b>& masks, float iou,
                                      float fit_ratio = 1.f);

struct DuplicateRepairCount {
  int duplicates = 0;  // masks found to be another box's object
  int regrown = 0;     // of those, replaced by GrabCut of their box
  int dropped = 0;     // of those, removed (repair drop, or a regrown mask under min_pixels)
};

// Repairs one view's masks in place. masks[k].box_index names its box in `boxes`. rgb (CV_8UC3)
// and depth (CV_32F metres, or empty) are read by repair regrow only. Masks keep their order;
// dropped ones are erased.
DuplicateRepairCount repair_duplicate_masks(const cv::Mat& rgb, const cv::Mat& depth,
                                            const std::vector<Box>& boxes, std::vector<Mask>& masks,
                                            const DuplicateMaskOptions& options,
                                            const GrabCutOptions& grabcut);

}  // namespace gslift
