// What a prompt rules out of its instance's 3D growth (filter_3d.hpp, step 3): the Gaussians its
// 2D answers say are not the object. Two rules, each applied where the prompt carries what it
// needs:
//  - a mask prompt's silhouette: a Gaussian whose centre projects into the mask's view, in front
//    of the camera and inside the frame, at a pixel outside the mask (mask_silhouette.hpp; SAGA
//    validates its selection by the mask this way before it grows it);
//  - the prompt's vote (inference.prompt_lift, FlashSplat's closed form): a Gaussian whose vote
//    balance (A_1 - A_0) / |(A_0, A_1)| is below -outside_vote, one the voting views saw (almost)
//    only outside the prompt's masks. The vote leaves such a Gaussian out of the selection; the
//    ball query would take it back whenever it lies within reach, as the support under a DTU
//    object and the wall behind it do. Unseen Gaussians (balance 0) are not ruled out: filling
//    what no view saw is what growth is for. [gslift addition, issue 28: docs/saga.md]
#pragma once

#include <vector>

#include "nodes/inference/filter_3d.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/prompts.hpp"

namespace gslift {

// Instance k is prompt k's selection. means: N x 3 centres of the model the prompts were
// answered on; outside_vote in [0, 1] (1 = the vote rules nothing out). Throws InputError when a
// prompt's view is not in the capture or its vote balance has another size than the model.
GrowthExclusion prompt_growth_exclusion(const std::vector<float>& means, const Capture& capture,
                                        const PromptSet& prompts, double outside_vote);

}  // namespace gslift
