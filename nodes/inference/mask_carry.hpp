// A click's mask carried across the training views by their automatic masks, before lifting
// [gslift addition; the lever "the click's mask carried across views" of issue 28, after Gaga's
// memory bank (docs/references.md): masks of other views join an object by the overlap of what
// is already lifted].
//
// The per-pixel answer of the rendered features to a click (PromptSegmenter::view_mask) spreads
// to every surface whose feature resembles the clicked one. Automatic masks (SAM's, or their
// simulation) cut the view into objects; what they lack is which mask of which view is the
// clicked object. In the prompt's view it is the mask holding the click that agrees best with
// the features' answer (any granularity: the answer picks the whole table, not the table with
// the patient on it, where both masks hold the click). Lifted by FlashSplat's vote in that view
// alone, it gives a first set of Gaussians; in every other training view the masks that set,
// rendered, covers for at least `coverage` of their pixels are the object there. The final
// selection is the vote of all those masks (mask_vote_lifting.hpp).
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/masks.hpp"
#include "nodes/splat/pixel_rows.hpp"

namespace gslift {

// Of `candidates` (one view's automatic masks), the one holding a click (every pixel of
// `clicks`) and none of `others` (the clicks of the other prompts given with it, in the same
// view: they name other objects, so a mask merging two of them is neither's) with the highest
// IoU with `answer`; when there is none, the 8-connected component of `answer` holding the first
// click (empty when the answer misses the click too).
cv::Mat1b clicked_mask(const std::vector<cv::Mat1b>& candidates,
                       const std::vector<cv::Point>& clicks, const cv::Mat1b& answer,
                       const std::vector<cv::Point>& others = {});

// The pixels (255) where the Gaussians marked in `selected` blend to an accumulated weight of at
// least `threshold` (SAGA's rendered 0/1 mask at 0.5).
cv::Mat1b rendered_selection(const PixelRowsView& rows, int width, int height,
                             const std::vector<uint8_t>& selected, float threshold = 0.5f);

// The union of the `candidates` that `covered` (nonzero pixels) covers for at least `coverage`
// of their own pixels; empty (a 0x0 Mat) when none does.
cv::Mat1b covered_masks(const std::vector<cv::Mat1b>& candidates, const cv::Mat1b& covered,
                        double coverage);

// Per capture view, the masks of `masks` given for it if it is a training view (empty
// otherwise). Throws InputError as training_mask_views does.
std::vector<std::vector<cv::Mat1b>> masks_by_training_view(const Capture& capture,
                                                           const MaskSet& masks);

// Per prompt k, its mask `own[k]` lifted by FlashSplat's vote in its view `view[k]` alone (1 =
// the object's), with background bias `bias` (mask_vote_lifting.hpp).
std::vector<std::vector<uint8_t>> lift_in_own_views(const GaussianModel& model,
                                                    const Capture& capture,
                                                    const std::vector<int>& view,
                                                    const std::vector<cv::Mat1b>& own, double bias);

}  // namespace gslift
