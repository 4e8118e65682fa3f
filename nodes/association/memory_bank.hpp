// Gaga's 3D-aware memory bank made semantic-aware (Proto-SaGa §3.2, Eq. 9-16; METHODS.md §2.2):
// the inconsistent SAM partitions of the training views become one consistent label map each.
//
// For mask t of view k, the candidates G_k(t) are the Gaussians whose projected centre, rounded
// to a pixel, lies in the mask (Eq. 9; centres only, opacity ignored, as Gaga's projector.py).
// Depth criterion (Eq. 10 as Gaga's code does it): the image is cut into a patches x patches grid
// and, inside each patch, the front max(floor(delta_d n), 1) of the n candidates there are kept.
// Probability criterion (Eq. 14-15): the candidates ranked by sigma_{i,k}(t) = softmax(tau
// cos(w_k, f_i))_t, the top max(floor(delta_s E), 1) of the E candidates kept (the paper writes
// Rank < delta_s E; the floor of 1 keeps a mask of fewer than 5 candidates from being empty, as
// in the depth criterion). Both: the union (Eq. 16).
//
// The bank (Eq. 11-13): the first view gives one entry per mask; a later mask joins the entry e
// with the highest overlap gamma = |G n M(e)| / |G| when gamma >= threshold (M(e) <- M(e) u G),
// else becomes a new entry. gaga_compat reproduces Gaga's associate.py instead: gamma = |G n M(e)|
// / (|G| + |G n M(e)|) (it saturates at 0.5), a joined entry gains only Gaussians not yet in any
// entry, a new entry takes the whole G (so entries may overlap). Two masks of one view may join
// the same entry (nothing forbids it, in the paper or the code).
//
// Cost: integer sets throughout. Selection sorts the view's candidates once by (mask, patch,
// depth); the overlaps of a mask are counted through a per-Gaussian list of its entries, so a
// mask costs O(|G| x entries per Gaussian), never O(entries x |M(e)|).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "nodes/scene/camera.hpp"
#include "nodes/scene/capture.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/label_maps.hpp"
#include "param/param_table.hpp"

namespace gslift {

enum class AssociationCriteria { Depth, Probability, Both };
const EnumNames<AssociationCriteria>& association_criteria_names();  // depth, probability, both

struct MemoryBankOptions {
  AssociationCriteria criteria = AssociationCriteria::Both;  // Proto-SaGa Eq. 16; Gaga: depth
  double front_fraction = 0.2;        // delta_d (Gaga --front_percentage 0.2)
  double probability_fraction = 0.2;  // delta_s (Proto-SaGa: delta_s = delta_d)
  int patches = 32;                   // grid cells per side (Gaga --num_patch 32)
  double threshold = 0.1;             // delta (Gaga --overlap_threshold 0.1)
  bool gaga_compat = false;           // Gaga's code instead of its paper (see above)
};

const ParamTable<MemoryBankOptions>& memory_bank_param_table();

// Where each Gaussian centre lands in one view: the row-major pixel its centre rounds to, or -1
// when it is behind the camera (z <= 0) or outside the image; and its camera depth z.
struct ProjectedCentres {
  std::vector<int32_t> pixel;
  std::vector<float> depth;
};
ProjectedCentres project_centres(const std::vector<float>& means, const Camera& camera,
                                 const Pose& pose);

// Eq. 9-16 for every mask of one view: sets[t - 1] = the sorted ids of the Gaussians selected for
// mask t of `partition` (CV_32SC1, 0 = no mask, masks 1..max). `probability` (one per Gaussian:
// sigma_{i,k} of the mask its centre falls in, see gaussian_mask_probabilities) is needed by the
// probability criterion and ignored by the depth one.
std::vector<std::vector<uint32_t>> select_mask_gaussians(const cv::Mat1i& partition,
                                                         const ProjectedCentres& centres,
                                                         const std::vector<float>& probability,
                                                         const MemoryBankOptions& options);

// sigma_{i,k}(t_i) of Eq. 14 for every Gaussian i whose centre falls in a mask t_i of the view
// (0 elsewhere): softmax over the view classifier's classes of tau cos(w_c, f_i).
// features: N x dim; weights: classes x dim (class c = raw SAM id c, 0 = no mask).
std::vector<float> gaussian_mask_probabilities(const cv::Mat1i& partition,
                                               const ProjectedCentres& centres,
                                               const std::vector<float>& features, int dim,
                                               const std::vector<float>& weights, int classes,
                                               double tau);

class MemoryBank {
 public:
  MemoryBank(size_t gaussians, double threshold, bool gaga_compat);

  // Eq. 11-13 for one view, its masks in order: returns the bank label (entry index + 1) of each
  // mask t (labels[t - 1]). The first call initialises one entry per mask.
  std::vector<int> add_view(const std::vector<std::vector<uint32_t>>& sets);

  size_t entries() const { return entries_.size(); }
  const std::vector<uint32_t>& entry(size_t e) const { return entries_[e]; }  // unsorted ids
  // gamma of a set G against every entry (the formula of this bank's mode), for tests.
  std::vector<double> overlaps(const std::vector<uint32_t>& set) const;

 private:
  void insert(int entry, uint32_t gaussian);

  double threshold_;
  bool gaga_compat_;
  std::vector<std::vector<uint32_t>> entries_;
  std::vector<std::vector<int32_t>> member_of_;  // per Gaussian, the entries holding it
};

// The consistent map of a view: raw id t -> labels[t - 1], 0 stays 0.
cv::Mat1i relabel_partition(const cv::Mat1i& partition, const std::vector<int>& labels);

struct AssociationResult {
  LabelMapSet consistent;           // the training views' maps, ids = bank labels 1..entries
  std::vector<size_t> entry_sizes;  // Gaussians per bank entry
  std::vector<double> view_ms;      // association time per view (projection to relabelled map)
};

// The whole association: the training views of `partitions` in their order (Gaga: the training
// cameras in order; the first initialises the bank), each projected, selected and added to the
// bank. `classifiers` (one per training view, by name) and the model's features are needed by the
// probability criterion, may be null for depth. Throws InputError when a view is missing from the
// capture or the classifiers, sizes differ, or no training view has a partition.
AssociationResult associate_masks(const GaussianModel& model, const Capture& capture,
                                  const LabelMapSet& partitions, const ViewClassifiers* classifiers,
                                  const MemoryBankOptions& options);

}  // namespace gslift
