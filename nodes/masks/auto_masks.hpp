// Class-agnostic automatic masks from classical segmentation, written as SAM automatic masks, so
// SAGA's pipeline runs on a capture without SAM output. A fallback, not SAM: Felzenszwalb-
// Huttenlocher graph-based segmentation (IJCV 2004; OpenCV ximgproc) at several scales, one
// granularity per scale, coarse to fine (granularity 0 = the largest regions, like SAM's whole
// objects; 1, 2 = parts and subparts). Every segment of at least min_area pixels becomes a mask.
// Graph segmentation cuts at colour edges, so it splits textured objects and merges objects with
// their background where the colour runs on; how this compares with (simulated) SAM masks on the
// embedded OR is measured in docs/saga.md.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "nodes/masks/label_segments.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/masks.hpp"
#include "param/param_table.hpp"

namespace gslift {

struct AutoMaskOptions {
  // Graph-segmentation scale k per granularity (larger = bigger regions: a merge needs an edge
  // weaker than k / |C|), coarse to fine; values are for a 640-pixel-wide image and scale with
  // the image width [decision, measured in docs/saga.md].
  std::vector<double> scales = {2000, 500};
  double sigma = 0.8;  // Gaussian smoothing before segmenting (Felzenszwalb: 0.8)
  SegmentKeep keep;    // min_area, max_area_fraction, views (label_segments.hpp)
};

const ParamTable<AutoMaskOptions>& auto_mask_param_table();

// The masks of one RGB image (CV_8UC3), each with its granularity (index into scales) and
// score 1. Deterministic (no randomness).
std::vector<Mask> auto_masks(const cv::Mat& rgb, const AutoMaskOptions& options);

// auto_masks of every view of options.views that has RGB, in capture order (parallel over views).
// Throws InputError naming a view whose image cannot be read.
MaskSet auto_mask_set(const Capture& capture, const AutoMaskOptions& options);

// The ground-truth instance masks of the views of `which` that have an instance map, one mask per
// instance id, labelled with the id in decimal (masks_from_instance_map).
MaskSet ground_truth_masks(const Capture& capture, ViewSet which);

// Which channel of a mask image holds the mask: its grey level (DTU's mask/), or its alpha (the
// Blender scenes' RGBA renders, whose alpha is the exact object coverage).
enum class MaskChannel { Gray, Alpha };
const EnumNames<MaskChannel>& mask_channel_names();  // gray, alpha

// Binary object masks from image files, one per view (DTU's mask/0NN.png): the file whose stem is
// the view's name, or is the same number (view "000024", file "024.png"). The channel is read,
// resized to the view's size (area filter) and thresholded at > 127; the mask is labelled
// `label`. Views of `which` without a file get none; unreadable files, and files without alpha
// when alpha is asked for, are InputErrors.
MaskSet mask_folder(const Capture& capture, const std::filesystem::path& folder, ViewSet which,
                    const std::string& label, MaskChannel channel = MaskChannel::Gray);

}  // namespace gslift
