#include "nodes/boxes/grabcut_priors.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <atomic>

#include <tbb/parallel_for.h>

#include "base/errors.hpp"

namespace gslift {
namespace {

// The box as whole pixels clipped to the image (as grabcut_box_mask covers it).
cv::Mat1b box_region(const Box& box, const cv::Size& size) {
  cv::Mat1b m = cv::Mat1b::zeros(size);
  const int x1 = static_cast<int>(std::floor(box.x1)), y1 = static_cast<int>(std::floor(box.y1));
  const int x2 = static_cast<int>(std::ceil(box.x2)), y2 = static_cast<int>(std::ceil(box.y2));
  m(cv::Rect(x1, y1, x2 - x1, y2 - y1) & cv::Rect(0, 0, size.width, size.height)).setTo(255);
  return m;
}

}  // namespace

double prior_size(const DetectorPrior& prior) {
  return prior.mask.empty() ? double(prior.box.area()) : double(cv::countNonZero(prior.mask));
}

PriorLabels refine_priors(const cv::Mat& rgb, const cv::Mat& depth,
                          const std::vector<DetectorPrior>& priors,
                          const GrabcutPriorOptions& options) {
  grabcut_prior_param_table().validate(options, "boxes.grabcut_priors");
  const cv::Size size = rgb.size();
  std::vector<size_t> order;
  for (size_t i = 0; i < priors.size(); ++i) {
    const DetectorPrior& p = priors[i];
    if (!p.mask.empty() && p.mask.size() != size)
      throw InputError("boxes.grabcut_priors: a mask prior is " + std::to_string(p.mask.cols) +
                       "x" + std::to_string(p.mask.rows) + " in a " + std::to_string(size.width) +
                       "x" + std::to_string(size.height) + " view");
    if (p.score >= options.score_threshold && p.label >= 0) order.push_back(i);
  }
  // Algorithm 1 line 3: decreasing size, so later (smaller) priors overwrite supporting surfaces.
  if (options.sort_by_size)
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
      return prior_size(priors[a]) > prior_size(priors[b]);
    });
  std::vector<GrabCutMask> refined(order.size());
  tbb::parallel_for(size_t(0), order.size(), [&](size_t k) {
    const DetectorPrior& p = priors[order[k]];
    if (!options.refine) {
      refined[k].pixels = p.mask.empty() ? box_region(p.box, size) : cv::Mat1b(p.mask != 0);
    } else if (p.mask.empty()) {
      refined[k] = grabcut_box_mask(rgb, depth, p.box, options.grabcut);
    } else {
      refined[k] = grabcut_mask_prior(rgb, depth, p.mask, options.border_fraction, options.grabcut);
    }
  });
  PriorLabels out;
  out.labels = cv::Mat1i(size, -1);
  out.confidence = cv::Mat1f::zeros(size);
  for (size_t k = 0; k < order.size(); ++k) {
    const DetectorPrior& p = priors[order[k]];
    out.labels.setTo(p.label, refined[k].pixels);
    out.confidence.setTo(p.confidence, refined[k].pixels);
    ++out.painted;
    if (refined[k].found) ++out.refined;
  }
  return out;
}

DetectorPriorMaps detector_prior_maps(const Capture& capture, const BoxSet& boxes,
                                      const MaskSet& masks, const GrabcutPriorOptions& options) {
  DetectorPriorMaps out;
  out.priors.classes = semantic_classes(capture, options.classes);
  const int classes = out.priors.class_count();
  std::vector<const ViewBoxes*> view_boxes(capture.views.size(), nullptr);
  std::vector<const ViewMasks*> view_masks(capture.views.size(), nullptr);
  for (const ViewBoxes& vb : boxes.views) {
    const int v = capture.find_view(vb.view);
    if (v < 0)
      throw InputError("boxes.grabcut_priors: boxes name view '" + vb.view +
                       "' that the capture '" + capture.name + "' lacks");
    view_boxes[v] = &vb;
  }
  for (const ViewMasks& vm : masks.views) {
    const int v = capture.find_view(vm.view);
    if (v >= 0) view_masks[v] = &vm;
  }
  out.priors.views.resize(capture.views.size());
  std::atomic<int> painted{0}, refined{0}, unknown{0};
  tbb::parallel_for(size_t(0), capture.views.size(), [&](size_t v) {
    const View& view = capture.views[v];
    std::vector<DetectorPrior> priors;
    if (view_boxes[v]) {
      for (size_t b = 0; b < view_boxes[v]->boxes.size(); ++b) {
        const Box& box = view_boxes[v]->boxes[b];
        DetectorPrior p;
        p.label = class_index(out.priors.classes, box.label);
        p.score = box.score;
        const int rounds = std::max(1, view_boxes[v]->rounds);
        p.confidence = options.confidence == PriorConfidence::Score
                           ? std::min(box.score, options.max_confidence)
                           : options.max_confidence * std::min(1.f, float(box.support) / rounds);
        p.box = box;
        if (p.label < 0) {
          ++unknown;
          continue;
        }
        if (options.kind == PriorKind::Mask && view_masks[v])
          for (const Mask& m : view_masks[v]->masks)
            if (m.box_index == static_cast<int>(b)) p.mask = m.pixels;
        priors.push_back(std::move(p));
      }
    }
    const int w = view.camera.width, h = view.camera.height;
    PriorLabels labels{cv::Mat1i(h, w, -1), cv::Mat1f::zeros(h, w)};
    if (!priors.empty()) {
      const cv::Mat rgb = view.rgb.load();
      if (rgb.empty())
        throw InputError("boxes.grabcut_priors: view '" + view.name + "' has no RGB image");
      const cv::Mat depth = options.grabcut.use_depth ? view.depth.load() : cv::Mat();
      labels = refine_priors(rgb, depth, priors, options);
    }
    painted += labels.painted;
    refined += labels.refined;
    out.priors.views[v] =
        label_confidence_view(view.name, labels.labels, labels.confidence, classes);
  });
  out.painted = painted;
  out.refined = refined;
  out.unknown_labels = unknown;
  return out;
}

const EnumNames<PriorConfidence>& prior_confidence_names() {
  static const EnumNames<PriorConfidence> names = {{PriorConfidence::Score, "score"},
                                                   {PriorConfidence::Support, "support"}};
  return names;
}

const EnumNames<PriorKind>& prior_kind_names() {
  static const EnumNames<PriorKind> names = {{PriorKind::Mask, "mask"}, {PriorKind::Box, "box"}};
  return names;
}

const ParamTable<GrabcutPriorOptions>& grabcut_prior_param_table() {
  using O = GrabcutPriorOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("kind", &O::kind, prior_kind_names(),
               "mask: a detection's mask where it has one, else its box; box: always the box")
          .add("confidence", &O::confidence, prior_confidence_names(),
               "what a prior's pixels get: score (the detection's, capped at max_confidence) or "
               "support (max_confidence x the fraction of VLM rounds that found it)")
          .add("max_confidence", &O::max_confidence,
               "cap of a prior's confidence (a VLM box scores 1; a certain prior can never be "
               "outvoted by the 3D source or the other views)",
               0, 1)
          .add("refine", &O::refine, "refine each prior with GrabCut (false: paint it as it is)")
          .add("sort_by_size", &O::sort_by_size,
               "paint priors in decreasing size so objects overwrite what they stand on "
               "(paper 002); false: detector order")
          .add("border_fraction", &O::border_fraction,
               "f of a mask prior's probable-foreground band t = f (w + h) / pi (paper: 0.1)", 0,
               10)
          .add("score_threshold", &O::score_threshold,
               "detections scoring below this are dropped (paper: 0.5)", 0, 1)
          .add("classes", &O::classes,
               "class vocabulary, ids 1..N (give the same to fusion.render_semantics); empty = "
               "the capture's ground-truth class names")
          .nest(&O::grabcut, grabcut_param_table());
  return table;
}

}  // namespace gslift
