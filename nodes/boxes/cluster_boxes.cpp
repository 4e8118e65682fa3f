#include "nodes/boxes/cluster_boxes.hpp"

#include <algorithm>
#include <cctype>
#include <map>
#include <numeric>
#include <set>

namespace gslift {
namespace {

std::string normalised_label(const std::string& label) {
  size_t begin = 0, end = label.size();
  while (begin < end && std::isspace(static_cast<unsigned char>(label[begin]))) ++begin;
  while (end > begin && std::isspace(static_cast<unsigned char>(label[end - 1]))) --end;
  std::string out = label.substr(begin, end - begin);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// Index of each candidate among the boxes of its own round, in input order.
std::vector<int> index_in_round(const std::vector<Box>& candidates) {
  std::map<int, int> next;
  std::vector<int> index(candidates.size());
  for (size_t i = 0; i < candidates.size(); ++i) index[i] = next[candidates[i].round]++;
  return index;
}

}  // namespace

std::vector<double> consensus_scores(const std::vector<Box>& candidates) {
  const size_t t = candidates.size();
  std::vector<double> score(t, 0.0);
  if (t < 2) return score;
  for (size_t i = 0; i < t; ++i) {
    double sum = 0;
    for (size_t j = 0; j < t; ++j)
      if (j != i) sum += iou(candidates[i], candidates[j]);
    score[i] = sum / static_cast<double>(t - 1);
  }
  return score;
}

std::vector<Box> cluster_boxes(const std::vector<Box>& candidates, int rounds,
                               const BoxClusteringParams& params) {
  const std::vector<double> score = consensus_scores(candidates);
  const std::vector<int> round_index = index_in_round(candidates);
  // Seeds in decreasing Eq. 2 score; equal scores in input order (stable sort).
  std::vector<size_t> order(candidates.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return score[a] > score[b]; });

  const int min_support = std::max(1, std::min(params.min_support, std::max(rounds, 1)));
  std::vector<char> assigned(candidates.size(), 0);
  std::vector<Box> out;
  for (const size_t seed : order) {
    if (assigned[seed]) continue;
    // Members in seed-score order, so the first member of a tied label has the highest score.
    std::vector<size_t> members;
    const std::string seed_label = normalised_label(candidates[seed].label);
    auto joins = [&](size_t j) {
      if (j == seed) return true;
      const double overlap = iou(candidates[seed], candidates[j]);
      return overlap > std::max(params.any_label_iou, params.iou) ||
             (overlap > params.iou && normalised_label(candidates[j].label) == seed_label);
    };
    for (const size_t j : order)
      if (!assigned[j] && joins(j)) {
        members.push_back(j);
        assigned[j] = 1;
      }
    std::set<int> rounds_seen;
    std::map<std::string, int> votes;
    for (const size_t j : members) {
      rounds_seen.insert(candidates[j].round);
      ++votes[normalised_label(candidates[j].label)];
    }
    const int support = static_cast<int>(rounds_seen.size());
    if (support < min_support) continue;
    const int best_votes =
        std::max_element(votes.begin(), votes.end(), [](const auto& a, const auto& b) {
          return a.second < b.second;
        })->second;
    std::string label;
    for (const size_t j : members) {
      const std::string l = normalised_label(candidates[j].label);
      if (votes[l] == best_votes) {
        label = l;
        break;
      }
    }
    Box representative = candidates[seed];
    representative.label = label;
    representative.support = support;
    if (representative.source_index < 0) representative.source_index = round_index[seed];
    out.push_back(std::move(representative));
  }
  return out;
}

BoxSet cluster_box_set(const BoxSet& boxes, const BoxClusteringParams& params) {
  BoxSet out;
  for (const ViewBoxes& view : boxes.views)
    out.views.push_back({view.view, view.rounds, cluster_boxes(view.boxes, view.rounds, params)});
  return out;
}

const ParamTable<BoxClusteringParams>& box_clustering_param_table() {
  using P = BoxClusteringParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .add("iou", &P::iou,
               "boxes with the seed's label join its cluster when their IoU with it exceeds this",
               0, 1)
          .add("any_label_iou", &P::any_label_iou,
               "boxes with another label join only above this IoU (1 = never; = iou: "
               "label-blind, as in the paper)",
               0, 1)
          .add("min_support", &P::min_support,
               "drop clusters seen in fewer distinct rounds (clamped to the rounds asked)", 1);
  return table;
}

}  // namespace gslift
