// Agreement between two flat clusterings of the same points (labels per point; -1, noise, is
// treated as one more label, as scikit-learn's adjusted_rand_score does).
#pragma once

#include <vector>

namespace gslift {

// Hubert & Arabie's adjusted Rand index: (RI - E[RI]) / (max RI - E[RI]) from the contingency
// table; 1 for identical partitions, about 0 for independent ones. 1 when both partitions are
// trivial in the same way (scikit-learn's convention). Throws std::invalid_argument on a size
// mismatch.
double adjusted_rand_index(const std::vector<int>& a, const std::vector<int>& b);

// True when the two labelings are the same partition up to renaming the labels, noise included
// (-1 must map to -1).
bool same_partition(const std::vector<int>& a, const std::vector<int>& b);

}  // namespace gslift
