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
// rendered, covers for at least `coverage` of their pixels are the object there, and so are the
// masks holding most of that rendered set and of no other prompt's (the whole object, where the
// click's mask was a part of it). The final selection is the vote of all those masks
// (mask_vote_lifting.hpp).
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/masks.hpp"
#include "nodes/splat/pixel_rows.hpp"

namespace gslift {

// Of `candidates` (one view's automatic masks), the one holding a click (every pixel of `clicks`)
// and none of `others` (the clicks of the other prompts given with it, in the same view: they name
// other objects, so a mask merging two of them is neither's) with the highest IoU with `answer`.
// When every mask holding the click holds another's too (the view's masks merged the clicked
// object with a clicked neighbour and have no mask of it alone), the one of those with the highest
// IoU with `answer`, with every mask holding another click and not this one cut out: its
// 8-connected piece holding the click, if that piece holds no other click. A click no candidate
// holds (SAM answers every click; its automatic masks leave gaps along thin parts and borders) is
// answered by the same rules at the nearest pixel of the masks that the answer's 8-connected piece
// under the click covers for at least half. Otherwise that piece of `answer` (empty when the
// answer misses the click too), which can spread far beyond the object (docs/saga.md).
cv::Mat1b clicked_mask(const std::vector<cv::Mat1b>& candidates,
                       const std::vector<cv::Point>& clicks, const cv::Mat1b& answer,
                       const std::vector<cv::Point>& others = {});

// Per selection k, the pixels (255) where the Gaussians marked in `selected[k]` blend to an
// accumulated weight of at least `threshold` (SAGA's rendered 0/1 mask at 0.5). One pass over the
// view's rows for all of them, parallel over image rows (each pixel's sums in row order: the same
// at any thread count).
std::vector<cv::Mat1b> rendered_selections(const PixelRowsView& rows, int width, int height,
                                           const std::vector<std::vector<uint8_t>>& selected,
                                           float threshold = 0.5f);

// The union of the `candidates` that `covered` (nonzero pixels) covers for at least `coverage`
// of their own pixels; empty (a 0x0 Mat) when none does.
cv::Mat1b covered_masks(const std::vector<cv::Mat1b>& candidates, const cv::Mat1b& covered,
                        double coverage);

// The union of the `candidates` that hold at least `containment` of `own`'s pixels (a prompt's
// rendered selection) and less than that share of each of `others` (the other prompts' rendered
// selections in the same view); empty when none does. Where a view's automatic masks cut an object
// into parts, the click's mask may be one part: the whole object's mask in another view holds all
// of the part's selection but is covered by it for less than half (covered_masks misses it).
// Holding most of another prompt's selection is what a mask merging two objects does: it is
// neither's (the rule clicked_mask applies to clicks in the prompt's view).
cv::Mat1b containing_masks(const std::vector<cv::Mat1b>& candidates, const cv::Mat1b& own,
                           const std::vector<cv::Mat1b>& others, double containment);

// A prompt's masks in a view other than its own, from its selection rendered there (`own`) and
// the selections that are not its object (`others`: the other prompts' and its stand-ins', see
// stand_in_masks): the masks its selection covers (covered_masks, `coverage`) and, when
// `containment` > 0, those holding its selection (containing_masks); empty when none.
cv::Mat1b carried_masks(const std::vector<cv::Mat1b>& candidates, const cv::Mat1b& own,
                        const std::vector<cv::Mat1b>& others, double coverage, double containment);

// The indices of the masks of a click's view (`candidates`) that stand in for the clicks a user did
// not give: those sharing no pixel with `own` (the click's mask there) or with any mask holding a
// click of `clicks`. They are other objects at every granularity the view's masks offer; lifted
// and rendered in the other views, they bound the containment rule as other prompts' selections
// do (a mask holding one of them merges the clicked object with it). Without them one click alone
// lets every mask holding its selection in, the whole table with the patient on it
// (docs/saga.md, "One click alone").
std::vector<size_t> stand_in_masks(const std::vector<cv::Mat1b>& candidates, const cv::Mat1b& own,
                                   const std::vector<cv::Point>& clicks);

// Per capture view, the masks of `masks` given for it if it is a training view (empty
// otherwise). Throws InputError as training_mask_views does.
std::vector<std::vector<cv::Mat1b>> masks_by_training_view(const Capture& capture,
                                                           const MaskSet& masks);

// Per capture view and per label of `labels`, the union of the masks of `masks` with that label in
// that view, when it is a training view that `masks` has masks for: an all-zero mask where the
// view has masks but none with the label (the object is not in sight there, so the whole view
// votes against it), an empty Mat where the view is held out or has no masks (it does not vote).
// The carry for masks given in every view, e.g. tracked through a video by a 2D segmenter, which
// is what FlashSplat lifts. Throws InputError as training_mask_views does, and when a label has
// no pixel in any training view.
std::vector<std::vector<cv::Mat1b>> labelled_masks_by_training_view(
    const Capture& capture, const MaskSet& masks, const std::vector<std::string>& labels);

// Per prompt k, its mask `own[k]` lifted by FlashSplat's vote in its view `view[k]` alone (1 =
// the object's), with background bias `bias` (mask_vote_lifting.hpp).
std::vector<std::vector<uint8_t>> lift_in_own_views(const GaussianModel& model,
                                                    const Capture& capture,
                                                    const std::vector<int>& view,
                                                    const std::vector<cv::Mat1b>& own, double bias);

}  // namespace gslift
