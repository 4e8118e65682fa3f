// The bottom-up semantic source of the detector-priors pipeline (paper 002 uses 3DEF's per-point
// class distributions; gslift renders those of the 3D pipeline): every Gaussian gets a class
// distribution, and a view's per-pixel distribution is their alpha-blend through the render cache
// (nodes/splat/render_cache.hpp: one sparse product F = W A over C channels), with the
// transmittance left after the last Gaussian given to the background distribution:
//   p(j | pixel) = sum_i w_i a_ij + T a_bg,j     (sum_i w_i + T = 1, so p sums to 1).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/semantic_maps.hpp"
#include "param/param_table.hpp"

namespace gslift {

struct RenderSemanticsOptions {
  // [decision] LangOR's instances carry a label but no probability: an instance's Gaussians say
  // "its label's class" with this confidence, the rest shared by the other classes. 0.8 keeps
  // the 3D source as sure as a detector prior just above its 0.5 threshold is unsure.
  float instance_confidence = 0.8f;
  // [decision] Unassigned Gaussians (LangOR leaves the room's walls, floor and ceiling
  // unassigned) and the transmittance left at a pixel say "background" with this confidence.
  float background_confidence = 0.8f;
  // The class vocabulary (ids 1..N); empty = the capture's ground-truth class names.
  std::vector<std::string> classes;
};

const ParamTable<RenderSemanticsOptions>& render_semantics_param_table();

// N x C per-Gaussian distributions (row-major). instance_class[k]: the class of instance k, -1
// when its label is none of the classes (its Gaussians get the uniform distribution); a Gaussian
// whose instance id is -1 gets the background distribution (class 0). Throws InputError when an
// id is beyond instance_class.
std::vector<float> gaussian_class_probabilities(const std::vector<int32_t>& instance_ids,
                                                const std::vector<int>& instance_class, int classes,
                                                const RenderSemanticsOptions& options);

// The background distribution of the options: class 0 with background_confidence.
std::vector<float> background_distribution(int classes, const RenderSemanticsOptions& options);

// A view's semantics from the weighted sum F (H x W x C, as RenderCache::render gives it) of
// per-Gaussian distributions that each sum to 1: adds (1 - sum_j F_j) times the background
// distribution per pixel and sets the argmax labels.
SemanticView semantics_from_blend(const std::string& view, std::vector<float> blend,
                                  const std::vector<float>& background, int classes, int width,
                                  int height);

// The rendered semantics of every capture view: instance k's class is the capture class named
// instance_labels[k] (semantic_classes, class_index; -1 when none, counted in `unknown`). One
// view at a time: a render cache holds millions of (pixel, Gaussian) pairs. Throws InputError
// when the model has no instance ids or the capture no class vocabulary.
SemanticMaps render_semantic_maps(const GaussianModel& model,
                                  const std::vector<std::string>& instance_labels,
                                  const Capture& capture, const RenderSemanticsOptions& options,
                                  int* unknown = nullptr);

}  // namespace gslift
