// "Did you mean" suggestions for misspelt names (node types, ids, ports, params, keys).
#pragma once

#include <string>
#include <vector>

namespace gslift {

// Levenshtein distance (insertions, deletions, substitutions each cost 1).
size_t edit_distance(const std::string& a, const std::string& b);

// The candidate closest to `name` by edit distance, if it is close enough to be a plausible typo
// (distance <= max(2, |name| / 3)); ties go to the earlier candidate. Empty when none is.
std::string nearest_name(const std::string& name, const std::vector<std::string>& candidates);

// A diagnostic hint: "did you mean 'x'?" when a candidate is close; otherwise, when
// `list_when_far` and there are candidates, "expected one of: a, b, c"; otherwise empty.
std::string suggest(const std::string& name, const std::vector<std::string>& candidates,
                    bool list_when_far = false);

}  // namespace gslift
