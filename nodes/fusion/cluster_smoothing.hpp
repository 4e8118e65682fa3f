// Cluster smoothing (paper 002 §3.4, Algorithm 2 line 5): every pixel of a cluster of a 3D
// over-segmentation takes the cluster's most frequent label, and the confidences travel with it.
// The over-segmentation is oversegment_rgbd() (supervoxels.hpp) of each view's back-projected
// depth: the paper takes its clusters from 3DEF's VCCS supervoxels of the frame's point cloud.
#pragma once

#include <opencv2/core.hpp>

#include "nodes/fusion/supervoxels.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/semantic_maps.hpp"

namespace gslift {

struct ClusterSmoothingResult {
  SemanticView smoothed;
  int clusters = 0;       // clusters with at least one labelled pixel
  long long changed = 0;  // pixels whose label changed
};

// clusters: CV_32S of the view's size, cluster id >= 0 per pixel, -1 = in no cluster (left as
// is). Per cluster: the majority label among its pixels' labels >= 0 (ties to the lowest class
// id); every pixel of the cluster takes it, with the mean distribution of the cluster's pixels
// that carry it [decision: the paper propagates "the respective confidences" without saying
// whose; the mean over the majority's pixels is the order-free choice]. Pixels whose label is -1
// count for no label, and a cluster with no labelled pixel stays as it is. Throws InputError
// when the sizes differ.
ClusterSmoothingResult smooth_clusters(const SemanticView& view, const cv::Mat1i& clusters,
                                       int classes);

// Every view of `maps` smoothed over the supervoxels (oversegment_rgbd) of its capture view's RGB
// and depth prior, in parallel over views; clusters and changed summed over the views. Throws
// InputError when a view is not in the capture or lacks RGB or depth.
SemanticMaps smooth_cluster_maps(const SemanticMaps& maps, const Capture& capture,
                                 const SupervoxelOptions& options, long long* clusters = nullptr,
                                 long long* changed = nullptr);

}  // namespace gslift
