// The index order that NumPy's default np.argsort (kind="quicksort", NumPy <= 1.24 scalar path)
// gives an array of doubles. Python hdbscan's generic algorithm sorts its minimum-spanning-tree
// edges with it, and the order of EQUAL weights decides how tied merges nest in the single-linkage
// tree; any order is a valid hierarchy, but reproducing this one makes our partitions identical to
// the reference on tied data (iris, digits in ../shared/data/hdbscan_reference).
#pragma once

#include <cstdint>
#include <vector>

namespace gslift {

// NumPy's introsort: median-of-3 quicksort, insertion sort for partitions of <= 16 elements
// (SMALL_QUICKSORT 15), heapsort once the recursion depth exceeds 2 floor(log2 n). Not stable.
std::vector<int64_t> numpy_argsort(const std::vector<double>& values);

}  // namespace gslift
