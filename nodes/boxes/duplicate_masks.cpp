#include "nodes/boxes/duplicate_masks.hpp"

#include <algorithm>

#include <opencv2/imgproc.hpp>

#include "nodes/boxes/box_masks.hpp"

namespace gslift {

double box_fit(const Box& box, const cv::Mat1b& mask) {
  const cv::Rect r = cv::boundingRect(mask);
  if (r.area() == 0) return 0.0;
  Box bounds;
  bounds.x1 = static_cast<float>(r.x);
  bounds.y1 = static_cast<float>(r.y);
  bounds.x2 = static_cast<float>(r.x + r.width);
  bounds.y2 = static_cast<float>(r.y + r.height);
  return iou(box, bounds);
}

std::vector<int> find_duplicate_masks(const std::vector<Box>& boxes,
                                      const std::vector<cv::Mat1b>& masks, float iou,
                                      float fit_ratio) {
  const size_t n = masks.size();
  std::vector<double> fit(n);
  for (size_t i = 0; i < n; ++i) fit[i] = box_fit(boxes[i], masks[i]);
  std::vector<int> owner(n, -1);
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < n; ++j) {
      if (i == j || boxes[i].label == boxes[j].label || fit_ratio * fit[j] <= fit[i]) continue;
      if (owner[i] >= 0 && fit[j] <= fit[owner[i]]) continue;
      if (mask_iou(masks[i], masks[j]) >= iou) owner[i] = static_cast<int>(j);
    }
  return owner;
}

DuplicateRepairCount repair_duplicate_masks(const cv::Mat& rgb, const cv::Mat& depth,
                                            const std::vector<Box>& boxes, std::vector<Mask>& masks,
                                            const DuplicateMaskOptions& options,
                                            const GrabCutOptions& grabcut) {
  DuplicateRepairCount count;
  if (options.repair == DuplicateRepair::Keep || masks.empty()) return count;
  std::vector<Box> mask_boxes;
  std::vector<cv::Mat1b> pixels;
  for (const Mask& m : masks) {
    mask_boxes.push_back(boxes.at(static_cast<size_t>(m.box_index)));
    pixels.push_back(m.pixels);
  }
  const std::vector<int> owner =
      find_duplicate_masks(mask_boxes, pixels, options.iou, options.fit_ratio);
  std::vector<bool> drop(masks.size(), false);
  for (size_t i = 0; i < masks.size(); ++i) {
    if (owner[i] < 0) continue;
    ++count.duplicates;
    if (options.repair == DuplicateRepair::Drop) {
      drop[i] = true;
      continue;
    }
    // Every other box's object, as the view's masks found it, is not this box's object.
    cv::Mat1b others = cv::Mat1b::zeros(pixels[i].size());
    for (size_t k = 0; k < pixels.size(); ++k)
      if (k != i) others |= pixels[k];
    const GrabCutMask g = grabcut_box_mask(rgb, depth, mask_boxes[i], grabcut, others);
    if (!g.found || cv::countNonZero(g.pixels) < options.min_pixels) {
      drop[i] = true;
      continue;
    }
    masks[i].pixels = g.pixels;
    ++count.regrown;
  }
  std::vector<Mask> kept;
  for (size_t i = 0; i < masks.size(); ++i)
    if (!drop[i]) kept.push_back(std::move(masks[i]));
  count.dropped = static_cast<int>(masks.size() - kept.size());
  masks = std::move(kept);
  return count;
}

const EnumNames<DuplicateRepair>& duplicate_repair_names() {
  static const EnumNames<DuplicateRepair> names = {{DuplicateRepair::Keep, "keep"},
                                                   {DuplicateRepair::Drop, "drop"},
                                                   {DuplicateRepair::Regrow, "regrow"}};
  return names;
}

const ParamTable<DuplicateMaskOptions>& duplicate_mask_param_table() {
  using O = DuplicateMaskOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("duplicates", &O::repair, duplicate_repair_names(),
               "a box whose mask is another box's object (mask IoU >= duplicate_iou, other "
               "label, that box fits it better): keep (LangOR), drop the mask, or regrow it by "
               "GrabCut of its box with the view's other masks as background")
          .add("duplicate_iou", &O::iou,
               "mask IoU at which two differently labelled masks are one object", 0, 1)
          .add("duplicate_fit_ratio", &O::fit_ratio,
               "the mask is another box's only when the mask's own box fits it less than this "
               "times as well (IoU of box and mask's bounding rectangle)",
               0, 1)
          .add("duplicate_min_pixels", &O::min_pixels,
               "a regrown mask smaller than this (pixels) is dropped", 0, 1000000);
  return table;
}

}  // namespace gslift
