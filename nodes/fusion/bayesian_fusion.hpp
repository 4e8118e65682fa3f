// Bayesian fusion of two per-pixel label distributions (paper 002 §3.4, Algorithm 2 line 4):
//   p(j | z1, z2) = tau_j p(z1 | j) p(z2 | j),   J = argmax_j p(j | z1, z2),
// with tau the normalisation that makes the fused distribution sum to 1 (equal a-priori class
// probabilities, the two sources independent given the class: the 3D source and the detector rely
// on different features). In gslift z1 is the bottom-up 3D semantics rendered in the view
// (fusion.render_semantics) and z2 the detector priors refined by GrabCut (boxes.grabcut_priors).
#pragma once

#include "nodes/scene/semantic_maps.hpp"

namespace gslift {

// Fuses two views of one size (width x height, `classes` classes each). Where the product is zero
// for every class (two sources certain of different classes) the pixel takes the mean of the two
// distributions [decision: neither source overrides the other]. Labels are the argmax (ties to
// the lowest class id). Throws InputError when the two views differ in size.
SemanticView fuse_bayesian(const SemanticView& bottom_up, const SemanticView& top_down, int classes,
                           int width, int height);

// fuse_bayesian on every view of two maps with the same classes and views (same order), in
// parallel; `changed` (optional) counts the pixels whose label differs from the bottom-up one.
// Throws InputError when the classes or views differ.
SemanticMaps fuse_bayesian_maps(const SemanticMaps& bottom_up, const SemanticMaps& top_down,
                                long long* changed = nullptr);

}  // namespace gslift
