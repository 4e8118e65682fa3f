// A supervoxel-like over-segmentation of one RGB-D view, the clusters of cluster smoothing
// (paper 002 §3.4). The paper takes 3DEF's clusters: VCCS supervoxels (Papon et al. 2013) grown
// from seeds on a grid of resolution R_seed with the distance
//   D = sqrt(w_c D_c^2 + w_s D_s^2 / (3 R_seed^2) + w_n D_n^2)
// (D_c: Euclidean distance in normalised RGB, D_s: spatial distance), then merged by region
// growing. gslift clusters the view's back-projected depth with that distance, without the normal
// term, by SLIC-style iterations (Achanta et al. 2012) instead of VCCS's voxel-adjacency flow:
// seeds on a pixel grid, every pixel assigned to the nearest centre among those seeded in its own
// and the 8 surrounding grid cells, centres moved to the mean point and colour of their pixels;
// then every cluster is split into its 4-connected pieces, so no cluster spans two surfaces that
// only touch in 3D. [decision] Why this and not Open3D's DBSCAN or the Gaussians: a depth view
// is what the paper clusters; the pixel grid gives a bounded, deterministic cost (9 candidates per
// pixel per iteration) and clusters of comparable size everywhere, which DBSCAN does not.
#pragma once

#include <opencv2/core.hpp>

#include "nodes/scene/camera.hpp"
#include "param/param_table.hpp"

namespace gslift {

struct SupervoxelOptions {
  int seed_spacing = 16;          // pixels between grid seeds [decision: ~0.15 m at 4 m in the OR]
  double seed_resolution = 0.15;  // R_seed, metres: the spatial normalisation of D
  double colour_weight = 0.2;     // w_c (PCL's VCCS default colour importance)
  double spatial_weight = 0.4;    // w_s (PCL's VCCS default spatial importance)
  int iterations = 5;
};

const ParamTable<SupervoxelOptions>& supervoxel_param_table();

// rgb: CV_8UC3; depth: CV_32F metres (0 = invalid), both the camera's size. Returns CV_32S
// cluster ids 0..K-1 in raster order of first appearance, -1 where the depth is invalid. Parallel
// over rows; the result does not depend on the thread count.
cv::Mat1i oversegment_rgbd(const cv::Mat& rgb, const cv::Mat1f& depth, const Camera& camera,
                           const SupervoxelOptions& options);

}  // namespace gslift
