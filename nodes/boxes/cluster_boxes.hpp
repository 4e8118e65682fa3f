// LangOR §2.2 (robust VLM perceptor): multi-round VLM boxes of one view -> one robust box per
// object.
//
// The t candidate boxes of an image (all rounds together) are clustered by IoU, the cluster's
// representative is chosen by LangOR Eq. 2,
//   B*_k = argmax_{B_i in U_k} (1 / (t - 1)) sum_{j != i} IoU(B_i, B_j),
// with the sum over ALL t candidates of the image (as the paper writes it, not only over U_k), and
// the cluster's label is the majority vote of its members.
//
// Clustering [decision]: greedy, not single-linkage. Candidates are taken in decreasing Eq. 2
// consensus score; the best unassigned one seeds a cluster and every unassigned candidate whose
// IoU with the seed exceeds the threshold joins it (a candidate with another label only above a
// higher threshold, see BoxClusteringParams::any_label_iou). Single-linkage chains neighbouring
// objects through one sloppy in-between box (two surgeons side by side); greedy seeding cannot
// chain through a box that is not itself a seed, and because seeds come in score order the seed IS
// the Eq. 2 representative of its cluster. (A box overlapping two objects by more than the
// threshold and scoring above both would still seed and absorb both: the threshold must stay >=
// 0.5.) The VLM's own score is not used: Qwen-VL grounding gives none (all 1).
#pragma once

#include <string>
#include <vector>

#include "nodes/scene/boxes.hpp"
#include "param/param_table.hpp"

namespace gslift {

// Defaults measured on the embedded OR (seeds 0-4, 5 views each, 5 simulated VLM rounds: 283
// visible instances; a cluster is correct when its representative box came from a not yet
// matched instance), recall / precision:
//   preset   iou  min_support 1     min_support 2
//   default  0.3  0.837 / 0.898     0.813 / 0.987
//   default  0.5  0.975 / 0.890     0.951 / 0.996
//   default  0.7  1.000 / 0.793     0.996 / 0.986
//   hard     0.3  0.855 / 0.766     0.784 / 0.996
//   hard     0.5  0.975 / 0.688     0.933 / 0.989
//   hard     0.7  1.000 / 0.375     0.753 / 0.930
// min_support 2 removes nearly all hallucinations for 2-4 points of recall; iou 0.5 is the most
// robust across difficulty (0.7 splits jittery objects into duplicates on "hard", 0.3 merges
// neighbours). Label accuracy of the voted labels: 0.99 (default), 0.92 (hard).
struct BoxClusteringParams {
  // Two boxes with the same label are the same object when IoU(seed, box) > iou.
  double iou = 0.5;
  // Two boxes with different labels are the same object (one of them mislabelled, the vote
  // decides) only when IoU(seed, box) > any_label_iou [decision, measured in docs/langor.md]:
  // objects that rest on or stand at one another have boxes overlapping by more than `iou`
  // (the patient on the operating table, instruments on the instrument table, a surgeon under
  // the C-arm), and clustering them regardless of label let the larger cluster's vote erase the
  // other object in most views. Jittered boxes of one object overlap far more than that.
  // 1 = never merge different labels; iou = the label-blind clustering of the paper. Never below
  // iou (iou 1, "no clustering", merges nothing).
  double any_label_iou = 0.8;
  // Clusters supported by fewer distinct rounds are dropped as hallucinations. Clamped to the
  // number of rounds of the view, so single-round input (the "w/o clustering" ablation) keeps its
  // boxes.
  int min_support = 2;
};

// The params of boxes.cluster: one entry per field above.
const ParamTable<BoxClusteringParams>& box_clustering_param_table();

// LangOR Eq. 2 score of each candidate: mean IoU with the other t - 1 candidates (0 when t = 1).
std::vector<double> consensus_scores(const std::vector<Box>& candidates);

// Clusters the candidates of one view. Each output box is a copy of its cluster's representative
// with: label = majority label of the cluster (labels compared lower-cased with surrounding
// spaces trimmed; ties go to the label of the member with the highest Eq. 2 score), support =
// number of distinct rounds in the cluster, round/source_index = those of the representative
// (source_index: its index among its round's boxes, so its SAM mask can be found). Output in
// decreasing Eq. 2 score of the representatives. `rounds` = rounds asked (for the clamp).
std::vector<Box> cluster_boxes(const std::vector<Box>& candidates, int rounds,
                               const BoxClusteringParams& params);

// cluster_boxes on every view.
BoxSet cluster_box_set(const BoxSet& boxes, const BoxClusteringParams& params);

}  // namespace gslift
