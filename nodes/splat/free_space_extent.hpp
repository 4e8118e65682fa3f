// Silhouette rims (issue 11): a Gaussian of an object whose extent reaches past the object's
// silhouette draws the object over whatever lies behind that silhouette in a camera that sees it
// from the side. Its centre is on the object, so free-space pruning (free_space.hpp) keeps it,
// and the training views it was fitted in may see the overhang only edge-on. Every training view
// with a depth prior knows the overhang is wrong: the points of the Gaussian's extent beyond the
// silhouette project onto pixels that observe the floor or wall much further away, i.e. they sit
// in observed empty space. This step shrinks each axis of a Gaussian until the points at
// +-`sigmas` standard deviations along it leave every training view's free space (a projection
// onto the constraint, no gradient: the photometric loss then refits what is left).
#pragma once

#include <cstddef>
#include <vector>

#include "nodes/scene/gaussian_model.hpp"
#include "nodes/splat/free_space.hpp"

namespace gslift {

struct ExtentClampOptions {
  // The extent checked along each axis, in standard deviations; 0 = off. At 1.5 sigma a
  // Gaussian of opacity 1 still draws with alpha exp(-1.125) = 0.32.
  double sigmas = 0;
  double tolerance = 0.1;  // relative depth margin of the free-space test (as free_space.hpp)
  // Each clamp halves an axis at most this many times (a factor of 2^-halvings).
  int max_halvings = 4;
  bool active() const { return sigmas > 0; }
};

// True when point x lies in the observed free space of some view: it projects inside the view, in
// front of the camera, with camera depth z < (1 - tolerance) D at its pixel, D the observed depth
// there (a pixel without a depth says nothing). Unlike the centre test of free_space_counts this
// reads the pixel itself, not the 3x3 minimum: the points tested here are meant to be tested
// right at the silhouette.
bool in_observed_free_space(const Eigen::Vector3d& x, const std::vector<DepthObservation>& views,
                            double tolerance);

// Shrinks, in place, every axis a of every Gaussian whose centre is not itself in free space and
// for which mean +- sigmas * scale_a * axis_a is: the axis is halved until both points are out of
// free space (at most max_halvings times; the last halving is kept either way). Returns the
// number of axes shrunk. Parallel over Gaussians, deterministic.
size_t clamp_extent_to_free_space(GaussianModel& model, const std::vector<DepthObservation>& views,
                                  const ExtentClampOptions& options);

}  // namespace gslift
