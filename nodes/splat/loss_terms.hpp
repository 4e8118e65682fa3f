// The terms reconstruct() trains over, each in its own file (loss_term.hpp: the contract). A new
// term: its file (class and factory), its factory declared here and listed in make_loss_terms.
#pragma once

#include <memory>
#include <vector>

#include "nodes/splat/free_space.hpp"
#include "nodes/splat/loss_term.hpp"
#include "nodes/splat/reconstruct.hpp"

namespace gslift {

// What terms may need beyond the options: the training views' depth priors at full resolution
// (borrowed for the run).
struct TermSetup {
  const std::vector<DepthObservation>& observations;
};

using LossTerms = std::vector<std::unique_ptr<LossTerm>>;

// Each factory gives its term, or null when the options switch it off (weight 0).
// 3DGS's photometric loss, (1 - ssim_lambda) L1 + ssim_lambda D-SSIM, weight 1 (losses.hpp).
std::unique_ptr<LossTerm> photometric_term(const ReconstructOptions& o, const TermSetup& s);
// DN-Splatter's depth log-L1 against the depth prior (depth_weight).
std::unique_ptr<LossTerm> depth_term(const ReconstructOptions& o, const TermSetup& s);
// 1 - cos between rendered normals and the depth prior's (normal_weight).
std::unique_ptr<LossTerm> normal_term(const ReconstructOptions& o, const TermSetup& s);
// The mean smallest scale (scale_weight).
std::unique_ptr<LossTerm> flatness_term(const ReconstructOptions& o, const TermSetup& s);
// Extent along the training rays at the priors' silhouettes (edge_extent_weight,
// depth_edge_extent.hpp).
std::unique_ptr<LossTerm> edge_extent_term(const ReconstructOptions& o, const TermSetup& s);
// Opacity drawn in front of the depth prior (line_of_sight_weight, line_of_sight_loss.hpp).
std::unique_ptr<LossTerm> line_of_sight_term(const ReconstructOptions& o, const TermSetup& s);

// The terms the options switch on, in this order (the order their values are summed in; the loop
// evaluates them by stage, in this order within a stage).
LossTerms make_loss_terms(const ReconstructOptions& o, const TermSetup& s);

}  // namespace gslift
