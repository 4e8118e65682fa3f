#include "nodes/lifting/cluster_agreement.hpp"

#include <map>
#include <stdexcept>
#include <utility>

namespace gslift {
namespace {

double pairs(double count) {
  return count * (count - 1) / 2;
}

}  // namespace

double adjusted_rand_index(const std::vector<int>& a, const std::vector<int>& b) {
  if (a.size() != b.size())
    throw std::invalid_argument("adjusted_rand_index: the labelings have different sizes");
  std::map<std::pair<int, int>, double> table;
  std::map<int, double> rows, cols;
  for (size_t i = 0; i < a.size(); ++i) {
    table[{a[i], b[i]}] += 1;
    rows[a[i]] += 1;
    cols[b[i]] += 1;
  }
  double index = 0, sum_rows = 0, sum_cols = 0;
  for (const auto& [key, count] : table) index += pairs(count);
  for (const auto& [key, count] : rows) sum_rows += pairs(count);
  for (const auto& [key, count] : cols) sum_cols += pairs(count);
  const double total = pairs(static_cast<double>(a.size()));
  const double expected = total > 0 ? sum_rows * sum_cols / total : 0;
  const double maximum = (sum_rows + sum_cols) / 2;
  if (maximum == expected) return 1.0;  // both trivial (one cluster each, or all singletons)
  return (index - expected) / (maximum - expected);
}

bool same_partition(const std::vector<int>& a, const std::vector<int>& b) {
  if (a.size() != b.size()) return false;
  std::map<int, int> forward, backward;
  for (size_t i = 0; i < a.size(); ++i) {
    if ((a[i] == -1) != (b[i] == -1)) return false;
    const auto f = forward.emplace(a[i], b[i]).first;
    const auto r = backward.emplace(b[i], a[i]).first;
    if (f->second != b[i] || r->second != a[i]) return false;
  }
  return true;
}

}  // namespace gslift
