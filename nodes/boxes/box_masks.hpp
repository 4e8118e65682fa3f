// LangOR §3.1: one instance mask per clustered representative box.
//
// source = sam: SAM's mask prompted with the representative box itself, given as a MaskSet linked
// to the clusters by box_index (ingest.sam_masks kind box reads it for the clusters: VLM round and
// source_index -> sam_box/<stem>/round_<k>.json entry).
// source = grabcut: OpenCV GrabCut initialised with the box rectangle, on RGB and, when the view
// has a depth prior, on the depth rendered as an 8-bit image; the two foregrounds are OR-ed and an
// empty result keeps the box itself as the mask (Antonello et al., docs/references.md).
// source = auto: sam for the boxes whose mask the capture has, grabcut for the others.
//
// Measured on the default embedded OR capture (53 clustered boxes over 5 views at 640x480; mean
// IoU with the ground-truth instance filling most of each box): SAM masks 0.813, GrabCut on RGB
// 0.591 (3.0 s), GrabCut on RGB or depth 0.584 (6.9 s), the box itself 0.389. The depth pass is
// kept on by default as the paper does it, but on this capture it costs twice the time for no
// gain: use_depth=false is the cheaper choice there.
#pragma once

#include <string>

#include <opencv2/core.hpp>

#include "nodes/boxes/duplicate_masks.hpp"
#include "nodes/scene/boxes.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/masks.hpp"
#include "param/param_table.hpp"

namespace gslift {

// Where a box's mask comes from (see above).
enum class BoxMaskSource { Sam, Grabcut, Auto };
const EnumNames<BoxMaskSource>& box_mask_source_names();  // sam, grabcut, auto

// GrabCut as boxes.to_masks and boxes.grabcut_priors both run it (paper 002 Algorithm 1 REFINE).
struct GrabCutOptions {
  int iterations = 5;  // paper 002: 5
  // [decision] GrabCut runs on the box grown by this fraction of its width/height on each side
  // (at least 8 pixels), not on the whole image: the colour models of the background then
  // describe the object's surroundings, and a 640x480 view costs a crop instead of the image.
  float context = 0.5f;
  bool use_depth = true;  // also run GrabCut on the depth prior when the view has one
};

// Its params: grabcut_iterations, context, use_depth.
const ParamTable<GrabCutOptions>& grabcut_param_table();

struct BoxMaskOptions {
  BoxMaskSource source = BoxMaskSource::Auto;
  GrabCutOptions grabcut;
  DuplicateMaskOptions duplicates;  // what becomes of a mask that is another box's object
};

// The params of boxes.to_masks: source, grabcut_param_table(), duplicate_mask_param_table().
const ParamTable<BoxMaskOptions>& box_mask_param_table();

struct GrabCutMask {
  cv::Mat1b pixels;    // image size, 255 inside
  bool found = false;  // false: GrabCut found no foreground and pixels is the prior itself
};

// GrabCut of one box, initialised with its rectangle. rgb: CV_8UC3; depth: CV_32FC1 metres
// (0 = invalid) of the same size, or empty. background: image-size pixels (nonzero) that are
// definitely not the object (other objects' masks), or empty; with it the box minus background
// is probable foreground, and it is the prior kept when GrabCut finds nothing. The depth crop is
// mapped linearly from its valid range to 1..255 (invalid pixels 0) and replicated to three
// channels; the RGB and depth foregrounds are OR-ed. OpenCV's RNG is reseeded before each call, so
// the result does not depend on which thread runs it or what it ran before.
GrabCutMask grabcut_box_mask(const cv::Mat& rgb, const cv::Mat& depth, const Box& box,
                             const GrabCutOptions& options, const cv::Mat1b& background = {});

// GrabCut of one mask prior (paper 002 §3.4): a band of thickness t = f (w + h) / pi around the
// mask's border (w, h: its bounding box; f = border_fraction, paper 0.1) is probable foreground,
// the mask inside the band foreground, everything else background. [decision] The band lies on
// both sides of the border (the mask dilated minus the mask eroded by t): GrabCut can then both
// trim and grow a coarse mask. The crop, the depth pass and the OR are those of
// grabcut_box_mask. An empty result, or a crop without both background and foreground samples,
// keeps the mask itself (found = false). mask: CV_8UC1 of the image size, nonzero inside.
GrabCutMask grabcut_mask_prior(const cv::Mat& rgb, const cv::Mat& depth, const cv::Mat1b& mask,
                               float border_fraction, const GrabCutOptions& options);

struct BoxMaskResult {
  // One ViewMasks per ViewBoxes of the clusters (same order), one Mask per box in box order (less
  // the duplicates options.duplicates drops):
  // label = the box's label, box_index = its index in the ViewBoxes, score = the SAM score or the
  // box's score.
  MaskSet masks;
  int from_sam = 0, from_grabcut = 0, from_box = 0;  // how each mask was made
  DuplicateRepairCount duplicates;                   // summed over views
};

// Masks for every clustered box of every view, training and held-out. `sam`: SAM masks of the
// clusters' boxes, matched by view name and box_index (empty = none). Parallel over views and,
// within a view, over boxes (one view's images in memory per running view). Throws InputError
// when a view is unknown to the capture, when a SAM mask names a box the view lacks, or when
// source = sam and a box has no SAM mask.
BoxMaskResult box_masks(const BoxSet& clusters, const Capture& capture, const MaskSet& sam,
                        const BoxMaskOptions& options);

}  // namespace gslift
