// Detector prior refinement with GrabCut (paper 002 §3.4, Algorithm 1): every prior (a box, or a
// mask with its box) above the detector threshold is refined by GrabCut on RGB and on depth, the
// two foregrounds OR-ed (grabcut_box_mask / grabcut_mask_prior, box_masks.hpp: the GrabCut that
// boxes.to_masks runs too); the priors are painted in decreasing order of size, so a supporting
// surface (the instrument table, the operating table) comes before the objects on it and the
// objects, painted later, overwrite it. Each painted pixel gets its prior's class and score.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "nodes/boxes/box_masks.hpp"
#include "nodes/scene/boxes.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/masks.hpp"
#include "nodes/scene/semantic_maps.hpp"
#include "param/param_table.hpp"

namespace gslift {

// Which priors a detection gives: its mask where it has one (else its box), or its box always.
enum class PriorKind { Mask, Box };
const EnumNames<PriorKind>& prior_kind_names();  // mask, box

// The confidence a prior paints (paper 002: the detector's score). score: the detection's score,
// capped at max_confidence; support: max_confidence x the fraction of the VLM rounds that found
// the object (ViewBoxes::rounds, Box::support: LangOR's consensus).
enum class PriorConfidence { Score, Support };
const EnumNames<PriorConfidence>& prior_confidence_names();  // score, support

struct GrabcutPriorOptions {
  PriorKind kind = PriorKind::Mask;
  PriorConfidence confidence = PriorConfidence::Score;
  // [decision] A VLM grounding reply has no score (Qwen-VL: every box 1). A prior of confidence 1
  // gives every other class probability 0, and a zero survives every product: the 3D source
  // cannot change such a pixel, nor can any number of other views in multi-view fusion (a
  // contribution that would zero every class is skipped). Capped at 0.99 the priors still win
  // the single-view fusion against the 3D source's 0.8, but the views can outvote one another:
  // at seed 0, 320x240, final CA 80.3 at 1, 83.8 at 0.8, 83.9 at 0.9, 86.0 at 0.95, 87.9 at 0.99
  // (docs/detector_fusion.md: 5 seeds at 640x480, "certain priors").
  float max_confidence = 0.99f;
  bool refine = true;            // false: paint the priors as they are (no GrabCut)
  bool sort_by_size = true;      // paper 002: decreasing size; false keeps the detector's order
  float border_fraction = 0.1f;  // f of the mask prior's band t = f (w + h) / pi (paper: 0.1)
  float score_threshold = 0.5f;  // detections scoring below this are dropped (paper: 0.5)
  // The class vocabulary (ids 1..N); empty = the capture's ground-truth class names.
  std::vector<std::string> classes;
  GrabCutOptions grabcut;
};

const ParamTable<GrabcutPriorOptions>& grabcut_prior_param_table();

struct DetectorPrior {
  int label = -1;          // class id
  float score = 1.f;       // detector score, compared with the threshold
  float confidence = 1.f;  // what its pixels get
  Box box;
  cv::Mat1b mask;  // image size, nonzero inside; empty for a box prior
};

struct PriorLabels {
  cv::Mat1i labels;      // class id per pixel, -1 where no prior
  cv::Mat1f confidence;  // the painting prior's confidence, 0 where none
  int painted = 0;       // priors above the threshold
  int refined = 0;       // of those, GrabCut found a foreground for
};

// Size of a prior for the ordering: its mask's pixel count, or its box's area.
double prior_size(const DetectorPrior& prior);

// Algorithm 1 on one view. rgb: CV_8UC3; depth: CV_32F metres or empty; priors' masks of the
// image size. GrabCut runs in parallel over the priors (each reseeds OpenCV's RNG); painting is
// sequential in the sorted order (a stable sort: equal sizes keep the detector's order).
PriorLabels refine_priors(const cv::Mat& rgb, const cv::Mat& depth,
                          const std::vector<DetectorPrior>& priors,
                          const GrabcutPriorOptions& options);

struct DetectorPriorMaps {
  SemanticMaps priors;  // every capture view, in capture order
  int painted = 0, refined = 0;
  int unknown_labels = 0;  // detections whose label is none of the capture's classes (dropped)
};

// Algorithm 1 on every view of the capture. The detections of a view are its boxes in `boxes`;
// with kind = mask, a box's mask is the mask of `masks` whose box_index names it (boxes.to_masks'
// output: SAM's box-prompted mask or its GrabCut fallback). Labels are matched to the capture's
// classes by name (semantic_classes); each view's map becomes a distribution with
// label_confidence_view. Parallel over views. Throws InputError when a view is unknown to the
// capture, or has no RGB image.
DetectorPriorMaps detector_prior_maps(const Capture& capture, const BoxSet& boxes,
                                      const MaskSet& masks, const GrabcutPriorOptions& options);

}  // namespace gslift
