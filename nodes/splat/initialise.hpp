// Initial Gaussians for reconstruction (3DGS initialises from SfM points): one isotropic Gaussian
// per voxel of a point cloud taken from the capture's sparse points or from its depth prior
// back-projected, voxel-downsampled (Open3D) at the pixel footprint so the model starts with no
// more Gaussians than the images can resolve.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "param/param_table.hpp"

namespace gslift {

struct ColouredPoints {
  std::vector<Eigen::Vector3d> xyz;
  std::vector<Eigen::Vector3d> rgb;  // [0,1]
  // World-space unit normals from the depth prior (depth_normals.hpp), (0,0,0) where the depth
  // gives none; empty for sparse points.
  std::vector<Eigen::Vector3d> normals;
  // Median over the points of depth / focal length: the world size of one pixel at each point.
  // 0 for points without a view (sparse SfM points).
  double median_footprint = 0;
};

// Where the initial Gaussians come from. Depth: back-project the depth prior of the training
// views; Points: the capture's sparse points; Random: random points in the volume the training
// views see together (random_volume_points); Auto: depth when every training view has a depth
// prior, else points when the capture has them, else random.
enum class InitSource { Auto, Depth, Points, Random };
const EnumNames<InitSource>& init_source_names();  // auto, depth, points, random

// Which distance to the 3 nearest neighbours sets a point's initial scale: the root mean square
// (3DGS's distCUDA2) or the plain mean (OpenSplat: the mean of the 3 nearest distances).
enum class NeighbourDistance { Rms, Mean };
const EnumNames<NeighbourDistance>& neighbour_distance_names();  // rms, mean

struct InitialiseOptions {
  InitSource source = InitSource::Auto;
  // Keep every stride-th pixel in x and y when back-projecting (1 = all). The voxel filter below
  // decides the final density; the stride only bounds the work before it.
  int pixel_stride = 2;
  // Voxel edge = footprint_factor x median pixel footprint. 1 keeps one Gaussian per pixel of the
  // nearest view; larger trades detail for speed. [decision] 12: on the embedded OR (4 training
  // views at 640x480, 500 steps, 1 thread) factor 8 / 12 / 16 start from 68k / 30k / 16k
  // Gaussians, densification grows them to 87k / 65k / 60k, and the run takes 104 / 86 / 80 s CPU
  // for 29.52 / 29.49 / 29.34 dB train PSNR (bench/results/splat_recon_sweep.json): 12 loses
  // nothing measurable against 8.
  double footprint_factor = 12.0;
  // Used for sparse points only (no footprint there): voxel edge in metres, 0 = no downsampling.
  double points_voxel = 0.0;
  // Initial scale = scale_factor x the RMS distance to the 3 nearest neighbours (3DGS: 1).
  // [decision] 0.5: at 1, every pixel of the embedded OR blends ~150 Gaussians at opacity 0.1
  // (the rasterizer's cost); at 0.5 about a quarter as many, and the splats still overlap (their
  // 3-sigma radius is 1.5 neighbour spacings). Optimisation grows them where needed.
  double scale_factor = 0.5;
  NeighbourDistance scale_distance = NeighbourDistance::Rms;
  // Scale along the depth-prior normal as a fraction of the in-plane scale, the Gaussian rotated so
  // that this (shortest) axis is the normal. 1 = isotropic (3DGS). [decision] 0.3: with isotropic
  // Gaussians the rasterizer's normal (the shortest axis) is an arbitrary axis, so the normal loss
  // starts near 1 - cos = 0.8 and 500 steps cannot rotate 68k Gaussians into place (it ended at
  // 0.72); discs along the prior's surface start it near its floor (bench/splat_recon).
  double normal_thickness = 0.3;
  float opacity = 0.1f;  // initial opacity (3DGS)
  // Random initialisation: how many points, and the depth range of the rays they are drawn on as
  // fractions of the scene extent (scene_extent below: 1.1 x the largest distance of
  // a training camera from their centroid). [decision] 3DGS draws 100k points in a cube for its
  // synthetic scenes; 20k keep the CPU steps short, and densification adds where the images ask.
  int random_points = 20000;
  double random_near = 0.05;
  double random_far = 2.0;
  // A random point is kept when at least this fraction of the training views (and at least two)
  // see it. [decision] 0.2: 500 steps on DTU scan 24 (400x300, random init) give 13.2 / 16.3 /
  // 15.8 / 13.2 dB held-out at 0 / 0.2 / 0.4 / 0.6 (16.65 dB from its SfM points); the lego
  // subset (200x200, 1000 steps, white background) 13.2 dB at 0 and 15.2 at 0.2. Points seen by
  // one or two views sit in front of the object and overfit them; too high a fraction leaves
  // parts of the object that few views see empty.
  double random_min_views = 0.2;
  uint64_t seed = 0;  // random initialisation only
  int sh_degree = 0;
  int feature_dim = 0;
};

// Back-projects each training view's depth prior (CV_32F metres, 0 = invalid) to world points
// with the view's colours and the prior's normals. Throws InputError naming the view when a depth
// map does not match its image size.
ColouredPoints backproject_depth(const Capture& capture, const std::vector<int>& views,
                                 int pixel_stride);

// 3DGS's cameras_extent: 1.1 x the largest distance of a training camera centre from their
// centroid (1 when there is a single camera).
double scene_extent(const Capture& capture);

// The extent the reconstruction scales its lengths by (position learning rate, clone and prune
// scales): the larger of scene_extent and the median distance of the initial Gaussians from the
// training cameras' centroid. 3DGS's camera extent assumes cameras around the scene; a room
// filmed from inside along a short path has cameras 0.1 m apart looking at walls 2 m away
// (Replica room0: camera extent 0.122, so prune_max_scale 0.1 x extent pruned every Gaussian over
// 1.2 cm, all 2,756 of them, at the first density round; issue 29).
double reconstruction_extent(const Capture& capture, const std::vector<float>& means);

// Sparse points with colours as read from the capture (rgb / 255).
ColouredPoints sparse_points(const Capture& capture);

// For a capture with neither points nor depth (a calibrated rig, a NeRF-style transforms.json):
// `count` points drawn on random rays of the training views (a random view, a random pixel, a
// depth uniform in [near, far]) and kept when at least max(2, ceil(min_view_fraction x views))
// training views see them (in front of the camera and inside the image), so they fill the volume
// the views share; each takes the colour of the pixel its ray came through. Deterministic for a
// seed. Throws InputError when no two views share any of the volume.
ColouredPoints random_volume_points(const Capture& capture, const std::vector<int>& views,
                                    int count, double near, double far, double min_view_fraction,
                                    uint64_t seed);

// Gaussians at the voxel-downsampled points: colour as SH DC ((rgb - 0.5) / C0), scale s =
// options.scale_factor x the RMS (3DGS's distCUDA2) or mean (OpenSplat) distance to the 3 nearest
// neighbours (options.scale_distance; floored at sqrt(1e-7)), opacity options.opacity. Where the
// voxel's mean normal is defined (points with normals), the local z axis is rotated onto it and
// scaled by normal_thickness (scales s, s, s x thickness); elsewhere identity rotation and
// isotropic s. voxel <= 0 keeps every point.
GaussianModel gaussians_from_points(const ColouredPoints& points, double voxel,
                                    const InitialiseOptions& options);

// The whole initialisation: picks the source, computes the voxel size and builds the model.
// Throws InputError when the chosen source is empty.
GaussianModel initialise_gaussians(const Capture& capture, const InitialiseOptions& options);

}  // namespace gslift
