#include "nodes/boxes/box_masks.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <tbb/parallel_for.h>
#include <opencv2/imgproc.hpp>

#include "base/errors.hpp"

namespace gslift {
namespace {

// The box as whole pixels (pixel-corner convention: pixel u is covered when x1 < u + 1, u < x2),
// clipped to the image.
cv::Rect box_pixels(const Box& box, const cv::Size& size) {
  const int x1 = static_cast<int>(std::floor(box.x1)), y1 = static_cast<int>(std::floor(box.y1));
  const int x2 = static_cast<int>(std::ceil(box.x2)), y2 = static_cast<int>(std::ceil(box.y2));
  return cv::Rect(x1, y1, x2 - x1, y2 - y1) & cv::Rect(0, 0, size.width, size.height);
}

// Depth as the 8-bit, three-channel image GrabCut needs: valid depths mapped linearly from
// [min, max] of the crop to [1, 255], invalid 0. Empty when the crop has no depth contrast.
cv::Mat depth_image(const cv::Mat& depth) {
  double lo = 0, hi = 0;
  const cv::Mat valid = depth > 0;
  if (cv::countNonZero(valid) == 0) return {};
  cv::minMaxLoc(depth, &lo, &hi, nullptr, nullptr, valid);
  if (hi <= lo) return {};
  cv::Mat gray;
  depth.convertTo(gray, CV_8U, 254.0 / (hi - lo), 1.0 - 254.0 * lo / (hi - lo));
  gray.setTo(0, ~valid);
  cv::Mat three;
  cv::cvtColor(gray, three, cv::COLOR_GRAY2BGR);
  return three;
}

// GrabCut foreground (definite or probable) of `image`: initialised with `rect` when `init` is
// empty, else with the per-pixel GrabCut classes in `init` (CV_8U, the image's size).
cv::Mat1b grabcut_foreground(const cv::Mat& image, const cv::Rect& rect, const cv::Mat& init,
                             int iterations) {
  cv::Mat labels = init.clone(), background, foreground;
  // GrabCut's k-means draws from the thread's OpenCV RNG: a fixed state keeps the result
  // independent of scheduling.
  cv::theRNG().state = 0x9e3779b97f4a7c15ULL;
  cv::grabCut(image, labels, rect, background, foreground, iterations,
              init.empty() ? cv::GC_INIT_WITH_RECT : cv::GC_INIT_WITH_MASK);
  return (labels == cv::GC_FGD) | (labels == cv::GC_PR_FGD);
}

// The crop GrabCut runs on: `rect` grown by options.context of its size on each side (at least
// 8 pixels), clipped to the image.
cv::Rect context_crop(const cv::Rect& rect, const cv::Size& size, const GrabCutOptions& options) {
  const int grow_x = std::max(8, static_cast<int>(std::lround(options.context * rect.width)));
  const int grow_y = std::max(8, static_cast<int>(std::lround(options.context * rect.height)));
  return cv::Rect(rect.x - grow_x, rect.y - grow_y, rect.width + 2 * grow_x,
                  rect.height + 2 * grow_y) &
         cv::Rect(0, 0, size.width, size.height);
}

// GrabCut fits 5-component colour models to both sides of an initialisation: it needs samples of
// each.
bool has_both_sides(const cv::Mat1b& init) {
  const int background = cv::countNonZero(init == cv::GC_BGD);
  return background >= 10 && static_cast<int>(init.total()) - background >= 10;
}

// GrabCut on the RGB crop and, with use_depth, on the depth crop, OR-ed (paper 002 Algorithm 1
// lines 6-8); `init` as in grabcut_foreground, in crop coordinates. An empty foreground keeps
// `result` (the prior) as it is.
void refine_in_crop(const cv::Mat& rgb, const cv::Mat& depth, const cv::Rect& crop,
                    const cv::Rect& inner, const cv::Mat& init, const GrabCutOptions& options,
                    GrabCutMask& result) {
  cv::Mat1b found = grabcut_foreground(rgb(crop), inner, init, options.iterations);
  if (options.use_depth && !depth.empty()) {
    const cv::Mat image = depth_image(depth(crop));
    if (!image.empty()) found |= grabcut_foreground(image, inner, init, options.iterations);
  }
  if (cv::countNonZero(found) == 0) return;
  result.pixels.setTo(0);
  found.copyTo(result.pixels(crop));
  result.found = true;
}

}  // namespace

GrabCutMask grabcut_box_mask(const cv::Mat& rgb, const cv::Mat& depth, const Box& box,
                             const GrabCutOptions& options, const cv::Mat1b& background) {
  const cv::Size size = rgb.size();
  const cv::Rect rect = box_pixels(box, size);
  GrabCutMask result;
  result.pixels = cv::Mat1b::zeros(size);
  result.pixels(rect).setTo(255);
  if (!background.empty()) result.pixels.setTo(0, background);
  // GrabCut needs background samples outside the rectangle and a rectangle to segment.
  const cv::Rect crop = context_crop(rect, size, options);
  if (rect.width < 2 || rect.height < 2 || crop == rect) return result;
  const cv::Rect inner(rect.x - crop.x, rect.y - crop.y, rect.width, rect.height);
  if (background.empty()) {
    refine_in_crop(rgb, depth, crop, inner, {}, options, result);
    return result;
  }
  // The rectangle's initialisation, with the background pixels inside it made definite.
  cv::Mat1b init(crop.size(), static_cast<uchar>(cv::GC_BGD));
  init(inner).setTo(cv::GC_PR_FGD);
  init.setTo(cv::GC_BGD, background(crop));
  if (!has_both_sides(init)) return result;
  refine_in_crop(rgb, depth, crop, {}, init, options, result);
  return result;
}

GrabCutMask grabcut_mask_prior(const cv::Mat& rgb, const cv::Mat& depth, const cv::Mat1b& mask,
                               float border_fraction, const GrabCutOptions& options) {
  GrabCutMask result;
  result.pixels = cv::Mat1b::zeros(mask.size());
  result.pixels.setTo(255, mask);
  const cv::Rect rect = cv::boundingRect(mask);
  if (rect.width < 2 || rect.height < 2) return result;
  const cv::Rect crop = context_crop(rect, mask.size(), options);
  // Paper 002 §3.4: t = f r, r the radius of the circle whose perimeter is the box's.
  const int t = std::max(
      1, static_cast<int>(std::lround(border_fraction * (rect.width + rect.height) / CV_PI)));
  const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_ELLIPSE, {2 * t + 1, 2 * t + 1});
  const cv::Mat1b inside = mask(crop) != 0;
  cv::Mat1b grown, shrunk;
  cv::dilate(inside, grown, kernel);
  cv::erode(inside, shrunk, kernel, {-1, -1}, 1, cv::BORDER_CONSTANT, 0);
  cv::Mat1b init(crop.size(), static_cast<uchar>(cv::GC_BGD));
  init.setTo(cv::GC_PR_FGD, grown);
  init.setTo(cv::GC_FGD, shrunk);
  if (!has_both_sides(init)) return result;
  refine_in_crop(rgb, depth, crop, {}, init, options, result);
  return result;
}

BoxMaskResult box_masks(const BoxSet& clusters, const Capture& capture, const MaskSet& sam_masks,
                        const BoxMaskOptions& options) {
  const BoxMaskSource source = options.source;
  for (const ViewBoxes& vb : clusters.views)
    if (capture.find_view(vb.view) < 0)
      throw InputError("boxes.to_masks: boxes name view '" + vb.view + "' that the capture '" +
                       capture.name + "' lacks");

  // SAM masks of the representatives, by (view, box index).
  std::vector<std::map<int, Mask>> sam(clusters.views.size());
  if (source != BoxMaskSource::Grabcut) {
    for (size_t v = 0; v < clusters.views.size(); ++v) {
      const ViewBoxes& vb = clusters.views[v];
      for (const ViewMasks& vm : sam_masks.views) {
        if (vm.view != vb.view) continue;
        for (const Mask& m : vm.masks) {
          if (m.box_index < 0 || m.box_index >= static_cast<int>(vb.boxes.size()))
            throw InputError("boxes.to_masks: a SAM mask of view '" + vb.view + "' names box " +
                             std::to_string(m.box_index) + " of " +
                             std::to_string(vb.boxes.size()) +
                             " (the sam input must be prompted with these clusters)");
          sam[v].emplace(m.box_index, m);
        }
      }
    }
  }

  BoxMaskResult result;
  result.masks.views.resize(clusters.views.size());
  std::atomic<int> from_sam{0}, from_grabcut{0}, from_box{0};
  std::atomic<int> duplicates{0}, regrown{0}, dropped{0};
  tbb::parallel_for(size_t(0), clusters.views.size(), [&](size_t v) {
    const ViewBoxes& vb = clusters.views[v];
    const View& view = capture.views[capture.find_view(vb.view)];
    ViewMasks& out = result.masks.views[v];
    out.view = vb.view;
    out.masks.resize(vb.boxes.size());
    bool needs_grabcut = false;
    for (size_t b = 0; b < vb.boxes.size(); ++b) {
      if (sam[v].count(static_cast<int>(b))) continue;
      if (source == BoxMaskSource::Sam)
        throw InputError("boxes.to_masks: capture '" + capture.name + "' has no SAM mask for box " +
                         std::to_string(b) + " of view '" + vb.view + "' (round " +
                         std::to_string(vb.boxes[b].round) + ", entry " +
                         std::to_string(vb.boxes[b].source_index) +
                         " of sam_box/, input sam); source=auto falls back to GrabCut");
      needs_grabcut = true;
    }
    cv::Mat rgb, depth;
    if (needs_grabcut) {
      rgb = view.rgb.load();
      if (rgb.empty())
        throw InputError("boxes.to_masks: view '" + vb.view + "' has no RGB image for GrabCut");
      if (options.grabcut.use_depth) depth = view.depth.load();
    }
    tbb::parallel_for(size_t(0), vb.boxes.size(), [&](size_t b) {
      const Box& box = vb.boxes[b];
      Mask& mask = out.masks[b];
      auto it = sam[v].find(static_cast<int>(b));
      if (it != sam[v].end()) {
        mask = it->second;
        ++from_sam;
      } else {
        GrabCutMask g = grabcut_box_mask(rgb, depth, box, options.grabcut);
        mask.pixels = g.pixels;
        mask.score = box.score;
        ++(g.found ? from_grabcut : from_box);
      }
      mask.label = box.label;
      mask.box_index = static_cast<int>(b);
    });
    if (options.duplicates.repair == DuplicateRepair::Regrow && rgb.empty()) {
      rgb = view.rgb.load();
      if (options.grabcut.use_depth) depth = view.depth.load();
    }
    const DuplicateRepairCount c = repair_duplicate_masks(rgb, depth, vb.boxes, out.masks,
                                                          options.duplicates, options.grabcut);
    duplicates += c.duplicates;
    regrown += c.regrown;
    dropped += c.dropped;
  });
  result.duplicates = {duplicates, regrown, dropped};
  result.from_sam = from_sam;
  result.from_grabcut = from_grabcut;
  result.from_box = from_box;
  return result;
}

const EnumNames<BoxMaskSource>& box_mask_source_names() {
  static const EnumNames<BoxMaskSource> names = {{BoxMaskSource::Sam, "sam"},
                                                 {BoxMaskSource::Grabcut, "grabcut"},
                                                 {BoxMaskSource::Auto, "auto"}};
  return names;
}

const ParamTable<GrabCutOptions>& grabcut_param_table() {
  using O = GrabCutOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("grabcut_iterations", &O::iterations, "GrabCut iterations (paper: 5)", 1, 100)
          .add("context", &O::context,
               "GrabCut crop: the box grown by this fraction of its size on each side", 0, 10)
          .add("use_depth", &O::use_depth, "also run GrabCut on the depth prior, OR-ed");
  return table;
}

const ParamTable<BoxMaskOptions>& box_mask_param_table() {
  using O = BoxMaskOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("source", &O::source, box_mask_source_names(),
               "sam: the capture's SAM mask of the box (missing = bad input); grabcut: GrabCut on "
               "RGB and depth; auto: sam where present, else grabcut")
          .nest(&O::grabcut, grabcut_param_table())
          .nest(&O::duplicates, duplicate_mask_param_table());
  return table;
}

}  // namespace gslift
