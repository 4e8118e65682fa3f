// Per-view instance label maps (Proto-SaGa / Gaga): SAM's inconsistent partitions, the memory
// bank's consistent maps on the training views, and the predicted maps of held-out views. Ids
// are 32-bit in memory (Gaga's uint8 maps wrap past 255 ids, method-anchors §1.1) and written as
// 16-bit PNGs (write_label_png16), so a scene may have up to 65535 labels on disk.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "base/port_type.hpp"

namespace gslift {

struct LabelMap {
  std::string view;  // view name in the capture
  cv::Mat1i labels;  // 0 = unlabelled, 1.. = instance ids
};

struct LabelMapSet {
  std::vector<LabelMap> views;  // in capture view order
  int labels = 0;               // ids run over 1..labels
};

GSLIFT_PORT_TYPE(LabelMapSet, "LabelMapSet");

// Writes <view>_labels.png (16-bit ids, read back with read_label_map) for every map in `dir`, and
// with `rgb` (the capture's views by name; may be null) <view>_overlay.png: the view's RGB half
// blended with one colour per id (id 0 left as it is), captioned with a legend of the ids it shows
// (the largest first, at most kLegendIds). Throws InputError past 65535 ids.
struct Capture;
void write_label_map_files(const LabelMapSet& maps, const Capture* rgb,
                           const std::filesystem::path& dir);

// A colour per id, fixed by the id alone (splitmix64 of it), so one instance has one colour in
// every view and run.
cv::Vec3b label_colour(int id);

// An id map (CV_32SC1, 0 = none) painted with label_colour, black where 0.
cv::Mat3b label_image(const cv::Mat1i& ids);

// Proto-SaGa Eq. 6: one cosine classifier per training view over that view's raw SAM ids
// (class 0 = pixels no mask covers, classes 1..L_k = the view's masks): logits tau cos(w_c, F).
struct ViewClassifier {
  std::string view;
  int classes = 0;
  std::vector<float> weights;  // classes x dim, row c = w_c (not normalised: Eq. 6 divides)
};

struct ViewClassifiers {
  int dim = 0;
  double tau = 10;
  std::vector<ViewClassifier> views;  // training views, in capture order
};

GSLIFT_PORT_TYPE(ViewClassifiers, "ViewClassifiers");

// Gaga's lift: a 1x1 linear classifier over rendered features, logits W F + b, classes 0..L of a
// consistent LabelMapSet.
struct LabelClassifier {
  int dim = 0;
  int classes = 0;
  std::vector<float> weights;  // classes x dim
  std::vector<float> bias;     // classes
};

GSLIFT_PORT_TYPE(LabelClassifier, "LabelClassifier");

}  // namespace gslift
