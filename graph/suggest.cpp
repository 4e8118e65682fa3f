#include "graph/suggest.hpp"

#include <algorithm>

namespace gslift {

size_t edit_distance(const std::string& a, const std::string& b) {
  // Two-row dynamic programme over prefixes: row[j] = distance(a[0..i), b[0..j)).
  std::vector<size_t> prev(b.size() + 1), row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t substitute = prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      row[j] = std::min({prev[j] + 1, row[j - 1] + 1, substitute});
    }
    std::swap(prev, row);
  }
  return prev[b.size()];
}

std::string nearest_name(const std::string& name, const std::vector<std::string>& candidates) {
  const size_t limit = std::max<size_t>(2, name.size() / 3);
  std::string best;
  size_t best_distance = limit + 1;
  for (const auto& c : candidates) {
    const size_t d = edit_distance(name, c);
    if (d < best_distance) {
      best = c;
      best_distance = d;
    }
  }
  return best;
}

std::string suggest(const std::string& name, const std::vector<std::string>& candidates,
                    bool list_when_far) {
  if (auto near = nearest_name(name, candidates); !near.empty())
    return "did you mean '" + near + "'?";
  if (!list_when_far || candidates.empty()) return {};
  std::string all;
  for (const auto& c : candidates) all += (all.empty() ? "" : ", ") + c;
  return "expected one of: " + all;
}

}  // namespace gslift
