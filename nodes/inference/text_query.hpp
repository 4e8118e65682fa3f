// Answering text queries on a segmented Gaussian scene (LangOR §1.3 "Retrieval"): query ->
// embedding -> instances (instance_retrieval.hpp) -> their Gaussians (instance_ids) -> a mask
// rendered in any view, plus a per-pixel relevancy map.
//
// Rendering uses the render cache (nodes/splat/render_cache.hpp): the blend weights w_i of each
// view are recorded once, then any per-Gaussian scalar a_i renders as sum_i w_i a_i in one sparse
// product. With a_i = 1 for the selected Gaussians this is the accumulated alpha of the selection
// alone, thresholded at 0.5 [decision] into the mask; with a_i = the relevancy of Gaussian i's
// instance (0 when unassigned) it is the Gaussian-weighted blend of instance relevancies.
//
// Both a_i only depend on the Gaussian's instance, so QueryView also folds the weights once into
// one accumulated-alpha plane per instance, A_k(p) = sum_{i in k} w_i(p): a query's mask is then
// sum_{k selected} A_k(p) and its relevancy map sum_k r_k A_k(p), a few passes over the pixels
// instead of a pass over every (pixel, Gaussian) pair of the cache. Measured on the default
// embedded OR (640x480, ~80k Gaussians, ~12M cache entries): the sparse product took 6.7 to
// 15.3 ms per mask depending on the load of the machine (it is memory bound and parallel, so
// other processes on the two cores doubled it); the planes take well under 1 ms (docs/langor.md;
// bench_viewer times a query).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "nodes/inference/instance_retrieval.hpp"
#include "nodes/inference/view_alignment.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/instances.hpp"
#include "nodes/scene/text_encoder.hpp"
#include "nodes/scene/text_query_results.hpp"
#include "nodes/splat/render_cache.hpp"
#include "param/param_table.hpp"

namespace gslift {

// One view prepared for queries: the render cache of the model seen from it, and the
// accumulated-alpha plane of each instance of model.instance_ids (ids >= 0; -1 = none).
class QueryView {
 public:
  QueryView(const GaussianModel& model, const Camera& camera, const Pose& pose);

  // sum_i w_i a_i per pixel; `per_gaussian` has one value per Gaussian of the model.
  cv::Mat1f render(const std::vector<float>& per_gaussian) const;
  // Pixels where the selected Gaussians' accumulated alpha reaches `threshold`: 255 inside.
  cv::Mat1b mask(const std::vector<float>& indicator, float threshold) const;
  // The same through the instance planes: sum_k per_instance[k] A_k(p), i.e. render() of
  // gaussian_values(instance_ids, per_instance). Instances beyond the model's largest id
  // contribute nothing.
  cv::Mat1f render_instances(const Eigen::VectorXf& per_instance) const;
  // mask() of selection_indicator(instance_ids, .., instances): sum_{k in instances} A_k(p)
  // reaches `threshold`.
  cv::Mat1b instance_mask(const std::vector<int>& instances, float threshold) const;

 private:
  RenderCache cache_;
  std::vector<cv::Mat1f> instance_alpha_;  // A_k, one per instance id 0..max id
};

// Per Gaussian: value[instance_ids[g]], 0 where the id is -1 or out of range.
std::vector<float> gaussian_values(const std::vector<int32_t>& instance_ids,
                                   const Eigen::VectorXf& per_instance);
// Per Gaussian: 1 when its instance is one of `instances`, else 0.
std::vector<float> selection_indicator(const std::vector<int32_t>& instance_ids, int instance_count,
                                       const std::vector<int>& instances);

// How a query picks its instances. ClosedSet: argmax over the vocabulary of queries
// (instance_retrieval.hpp); Relevancy: every instance whose relevancy exceeds
// relevancy_threshold.
enum class QuerySelection { ClosedSet, Relevancy };
const EnumNames<QuerySelection>& query_selection_names();  // closed_set, relevancy

struct TextQueryOptions {
  QuerySelection selection = QuerySelection::ClosedSet;
  float relevancy_threshold = 0.5f;
  float mask_threshold = 0.5f;  // accumulated alpha of the selection that makes a pixel "in"
  float softmax_scale = 10.f;   // LangSplat's temperature in the relevancy softmax
  // Relevancy map as the weighted mean sum_i w_i r_i / sum_i w_i instead of the weighted sum
  // [decision, measured in docs/langor.md]: the mean removes the pixel's coverage (alpha < 1 at
  // silhouettes, sparse Gaussians) from the ranking, so the argmax follows relevancy alone.
  bool normalise_relevancy = false;
  std::vector<std::string> negatives = canonical_negatives();
  // Extra closed-set vocabulary entries that compete with the queries (e.g. every class name).
  // A query that lands on an entry (nodes/scene/vocabulary_match.hpp: its nearest entry, at the
  // encoder's match_threshold or above) stands for it: the entry leaves the closed set, so
  // "nurse" selects the circulating nurse instead of losing it to the class name itself.
  std::vector<std::string> vocabulary;
  // Each view's masks and relevancy maps moved by the shift registering the model's render there
  // to its photo (view_alignment.hpp; off by default, langor.yaml: docs/langor.md).
  MaskAlignment align;
};

// The params of inference.text_query that configure the answering: selection,
// relevancy_threshold, mask_threshold, normalise_relevancy, softmax_scale, align_to_photo,
// align_min_gain (negatives and vocabulary are not params).
const ParamTable<TextQueryOptions>& text_query_param_table();

// Selection only (no rendering): instances and their relevancies for every query, and the
// vocabulary entry each query lands on (results.query_classes). Throws
// InputError when the instances' semantics do not match the encoder's width.
void select_instances(const InstanceSet& instances, const TextEncoder& encoder,
                      const TextQueryOptions& options, TextQueryResults& results);

// Answers `queries` in the views `view_indices` of `capture`. The model must carry instance_ids
// (one per Gaussian, ids < instances.size() or -1); throws InputError otherwise. `alignments`
// (when given) receives each view's photo alignment (options.align), in the order of the views.
TextQueryResults answer_text_queries(const GaussianModel& model, const InstanceSet& instances,
                                     const TextEncoder& encoder, const Capture& capture,
                                     const std::vector<int>& view_indices,
                                     const std::vector<std::string>& queries,
                                     const TextQueryOptions& options,
                                     std::vector<PhotoAlignment>* alignments = nullptr);

}  // namespace gslift
