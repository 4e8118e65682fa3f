// Promptable 3D segmentation over per-Gaussian affinity features (SAGA, paper 001 §4.4).
//
// Queries come from the view the prompt is given in: the feature map F rendered there
// (sum_i w_i f_i, L2-normalised per pixel). Each Gaussian's feature f_g (L2-normalised) is scored
// against them, and the selection is the Gaussians that pass:
//  - point: positive / negative queries = F at the clicked pixels; S_p = max cos to the positives,
//    S_n = max cos to the negatives; keep S_p > S_n and S_p > tau. tau is fixed (0.75, the public
//    code's notebook) or adaptive: "the average of the largest positive scores" (paper), read here
//    as the mean of S_p over all Gaussians (each S_p is a Gaussian's largest positive score).
//  - scribble and mask (dense hints): K-means (K = 5) over F under the positive strokes / the mask
//    gives the positive queries, over the negative strokes the negative ones; then as points. The
//    outside of a mask can give K-means negative queries too (option mask_negatives, off: SAGA's
//    mask prompts carry negatives only when the user draws them).
//  - sam (a reference mask as SAM returns it): one query q = the masked average of F; accepted
//    when the 2D mask it induces in the view (pixels with <F, q> above the mean + std over the
//    view's pixels) covers >= 90% of the reference mask, and then Gaussians with <f_g, q> above
//    tau_SAM = mean + std of those scores over all Gaussians are kept; otherwise the prompt is
//    answered as a mask prompt (K-means queries). The paper pools SAM encoder features here
//    (its SAM-guidance loss); gslift has none and pools the affinity features.
#pragma once

#include <cstdint>
#include <vector>

#include "base/uninit_vector.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/masks.hpp"
#include "nodes/scene/prompts.hpp"
#include "param/param_table.hpp"

namespace gslift {

enum class PromptThreshold { Fixed, Adaptive };
const EnumNames<PromptThreshold>& prompt_threshold_names();  // fixed, adaptive

struct PromptOptions {
  PromptThreshold threshold = PromptThreshold::Fixed;
  double tau = 0.75;  // fixed threshold on S_p (SAGA notebook: sim > 0.75)
  int kmeans_k = 5;   // SAGA: 5 clusters per dense hint
  // Pixels of a dense hint given to K-means at most (every n-th pixel beyond that) [decision:
  // a 5-means of 4096 samples is stable and takes about a millisecond].
  int kmeans_pixels = 4096;
  double sam_coverage = 0.9;  // SAGA: the pooled query must cover 90% of the reference mask
  // Mask prompts: K-means negatives from the outside of the mask [decision: off by default, as
  // in SAGA; the object's rendered fringe just outside a tight mask becomes a negative query of
  // the object itself].
  bool mask_negatives = false;
  // Mask / sam prompts: keep only selected Gaussians whose centre projects into the mask in the
  // prompt's view (those projecting outside the view or behind the camera cannot be checked and
  // stay): SAGA §4.5 grows its region from "Gaussians validated by the 2D mask" [off by default,
  // measured on DTU in docs/saga.md].
  bool mask_validate = false;
  uint64_t seed = 0;  // not a param: the node's seed (K-means seeding)
};

const ParamTable<PromptOptions>& prompt_param_table();

struct PromptSelection {
  std::vector<float> score;       // per Gaussian: S_p (sam: <f_g, q>)
  std::vector<uint8_t> selected;  // per Gaussian: 1 = in the object
  float threshold = 0;            // the tau the scores were compared with
  int positive_queries = 0;
  int negative_queries = 0;
  bool pooled = false;  // sam prompts: the masked-average query was accepted
  int64_t count = 0;    // selected Gaussians
  // The normalised queries the scores came from (q x dim each), for view_mask.
  std::vector<float> positive, negative;
};

// The model's normalised features, and the feature maps of the views prompts were given in
// (rendered once per view, on first use). Not thread-safe: one prompt at a time.
class PromptSegmenter {
 public:
  // Throws InputError when the model has no features.
  PromptSegmenter(const GaussianModel& model, const Capture& capture, const PromptOptions& options);

  // Throws InputError for a prompt whose view is unknown, whose pixels lie outside the view,
  // whose mask is empty or differs in size from the view, or that has no positive part.
  PromptSelection select(const Prompt& prompt);

  // A point or scribble prompt given in any camera, not only one of the capture's (the orbit
  // camera of `gslift view`; prompt.view is not read), with `tau` as the fixed threshold (the
  // viewer's slider). The features are rendered in the smallest window of the camera that holds
  // the prompt's pixels (features_at): a click costs the model's projection and a pixel's
  // blending, not a whole feature map. Throws InputError as select() does, and for mask and sam
  // prompts.
  PromptSelection select_in_camera(const Prompt& prompt, const Camera& camera, const Pose& pose,
                                   double tau);

  // The normalised rendered feature map of view `v` (H x W x dim), rendered on first use.
  const UninitVector<float>& feature_map(int v);

  // The selection's answer in view `v` decided per pixel of the rendered feature map by the rule
  // that selected Gaussians (S_p > S_n and S_p > tau; a pooled sam query: above the mean + std
  // of the view's pixel scores, the paper's 2D rule): the prompt's mask carried to another view.
  cv::Mat1b view_mask(const PromptSelection& selection, int v);
  int dim() const { return dim_; }

 private:
  PromptSelection select_by_queries(const std::vector<float>& positive,
                                    const std::vector<float>& negative, double tau) const;
  std::vector<float> kmeans_queries(int v, const std::vector<uint32_t>& pixels);
  // K-means centres (normalised) of the rows of `map` (dim_ wide) at `pixels`, at most
  // kmeans_pixels of them, evenly strided.
  std::vector<float> kmeans_of_pixels(const float* map, const std::vector<uint32_t>& pixels) const;
  // The normalised features (a row per pixel) at `pixels` (row-major indices of `camera`),
  // rendered in the window of the camera that just holds them (its principal point shifted): a
  // pixel blends the Gaussians over its own centre, whatever the image around it.
  std::vector<float> features_at(const Camera& camera, const Pose& pose,
                                 const std::vector<uint32_t>& pixels) const;
  void validate_by_mask(PromptSelection& r, const cv::Mat1b& mask, const View& view) const;

  const GaussianModel& model_;
  const Capture& capture_;
  PromptOptions options_;
  int dim_ = 0;
  std::vector<float> unit_;                // N x dim, L2-normalised features (zero rows stay zero)
  std::vector<UninitVector<float>> maps_;  // per capture view, empty until rendered
};

// Per Gaussian: the index of the selection that holds it (the one with the highest score when
// several do), -1 when none: the instance ids that inference.filter_3d and the mask renderer
// take.
std::vector<int32_t> selection_instance_ids(const std::vector<PromptSelection>& selections);

// Prompts derived from reference masks (e.g. ground truth) of view `view`: one per non-empty
// mask, named by its label. point: one positive pixel at the mask's centroid, or at its innermost
// pixel (largest distance to the boundary) when the centroid falls outside a non-convex mask;
// mask and sam: the mask itself. Throws InputError for scribble (strokes come from a file) or a
// view without masks.
PromptSet prompts_from_masks(const MaskSet& reference, const std::string& view, PromptKind kind);

// The prompt of `set` named `name` alone, as a user who clicks one object gives it: no other
// prompt's click or selection then shapes its answer (the rules that keep prompts given together
// apart do not apply). Throws InputError naming the prompts there are when none has that name.
PromptSet prompt_named(const PromptSet& set, const std::string& name);

}  // namespace gslift
