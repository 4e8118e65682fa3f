// Multi-view frame fusion (paper 002 §3.2, after Antonello et al. 2018, ref. [18]): every pixel of
// a reference frame with a valid depth is back-projected to 3D and forward-projected into each
// other frame. Frame i contributes to the pixel when its forward projection lands in the image;
// it votes with the majority label of the 3x3 Moore neighbourhood around the projection, counting
// only the neighbours that pass the geometric validation of Eq. 1: the neighbour, back-projected
// with its own depth and brought into the reference camera, lies within epsilon of the reference
// point along the reference depth axis, |NP.z - P_ref.z| < epsilon. The frame's distribution is
// that of a neighbour carrying the majority label. The fused distribution is the product of the
// reference distribution and every contributing frame's (i.i.d. measurements, uniform class
// prior), normalised; a tie for the largest probability keeps the reference label.
#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "nodes/scene/camera.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/semantic_maps.hpp"
#include "param/param_table.hpp"

namespace gslift {

struct MultiviewFusionOptions {
  double epsilon = 0.05;  // metres, paper 002 Eq. 1: 0.05 m
  int neighbourhood = 1;  // half-width of the Moore neighbourhood (1 = 3x3, the paper's)
};

const ParamTable<MultiviewFusionOptions>& multiview_fusion_param_table();

// One frame: its camera (width, height, intrinsics), pose, depth (CV_32F metres, 0 = invalid,
// camera size) and semantics (camera size, `classes` classes).
struct FusionFrame {
  Camera camera;
  Pose pose;
  cv::Mat1f depth;
  const SemanticView* semantics = nullptr;
};

struct MultiviewFusionResult {
  SemanticView fused;
  long long contributions = 0;  // (pixel, other frame) pairs that passed validation and voted
  long long changed = 0;        // pixels whose label differs from the reference label
};

// Fuses frame `reference` with all the others. Neighbour ties: the label of the projected pixel
// itself when it is among the most voted, else the lowest label; the distribution is taken from
// the projected pixel when it carries the majority label, else from the first such neighbour in
// raster order. A contribution whose product with the running product is zero for every class
// (two certain, contradicting measurements) is skipped. Parallel over rows. Throws InputError
// when a frame's depth or semantics differ in size from its camera.
MultiviewFusionResult fuse_multiview(const std::vector<FusionFrame>& frames, int reference,
                                     int classes, const MultiviewFusionOptions& options);

// Every view of `maps` the reference in turn (paper 002 §3.2), in parallel over views, with the
// capture's cameras, poses and depth priors; contributions and changed summed over the views.
// Throws InputError when a view is not in the capture or has no depth prior.
SemanticMaps fuse_multiview_maps(const SemanticMaps& maps, const Capture& capture,
                                 const MultiviewFusionOptions& options,
                                 long long* contributions = nullptr, long long* changed = nullptr);

}  // namespace gslift
