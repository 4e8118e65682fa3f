// Per-pixel class distributions of some views (detector priors, a rendered 3D semantic source,
// their fusion): what the detector-priors pipeline (paper 002, docs/detector_fusion.md) passes
// from stage to stage. Class ids index `classes` (id 0 = background, as in Capture::classes).
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "base/port_type.hpp"
#include "nodes/scene/capture.hpp"

namespace gslift {

struct SemanticView {
  std::string view;  // view name in the capture
  // H x W x C class probabilities, pixel-major (pixel p's distribution starts at p * C); each
  // pixel's entries sum to 1. A pixel without information holds the uniform distribution.
  std::vector<float> probabilities;
  cv::Mat1i labels;      // H x W argmax class; -1 where the source says nothing (no prior)
  cv::Mat1f confidence;  // H x W probability of `labels` (1 / C where labels is -1)

  const float* pixel(int p, int classes) const {
    return probabilities.data() + size_t(p) * classes;
  }
  float* pixel(int p, int classes) { return probabilities.data() + size_t(p) * classes; }
};

struct SemanticMaps {
  std::vector<std::string> classes;  // C class names, index = class id
  std::vector<SemanticView> views;   // in capture view order

  int class_count() const { return static_cast<int>(classes.size()); }
};

GSLIFT_PORT_TYPE(SemanticMaps, "SemanticMaps");

// The capture's class names as a dense list, index = class id (0 = "background" when the
// capture does not name it). Throws InputError when the capture has no class vocabulary or its
// ids have gaps.
std::vector<std::string> semantic_classes(const Capture& capture);

// `given` class names as that list ("background" first, then the names in order: class ids 1..N)
// when there are any, else semantic_classes(capture): a capture without ground truth gets its
// vocabulary from the user, as LangOR's production graph gets its text queries.
std::vector<std::string> semantic_classes(const Capture& capture,
                                          const std::vector<std::string>& given);

// Index of `label` in `classes`, compared case-insensitively; -1 when it is none of them.
int class_index(const std::vector<std::string>& classes, const std::string& label);

// A view whose pixels each hold one label with one confidence (a detector prior, paper 002
// Algorithm 1): p(label) = confidence and the rest shared equally by the other classes, i.e. the
// detector's "this is label with probability s" with no preference among the alternatives; a
// pixel with label -1 gets the uniform distribution. labels: CV_32S, confidence: CV_32F, one size.
SemanticView label_confidence_view(const std::string& view, const cv::Mat1i& labels,
                                   const cv::Mat1f& confidence, int classes);

// Sets labels and confidence from the probabilities (argmax, ties to the lowest class id).
void set_argmax(SemanticView& view, int classes, int width, int height);

}  // namespace gslift
