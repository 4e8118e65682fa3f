// K-means (Lloyd 1982, k-means++ seeding by Arthur & Vassilvitskii 2007) over feature rows: SAGA
// turns dense prompts (scribbles, masks) into a few query features this way (paper 001 §4.4,
// K = 5 "as a rule of thumb").
#pragma once

#include <cstdint>
#include <vector>

namespace gslift {

struct KMeansResult {
  std::vector<float> centres;  // k x dim, row-major
  std::vector<int> labels;     // per row, its centre
  int k = 0;                   // min(requested k, rows)
  int iterations = 0;          // Lloyd iterations run (stops when no label changes)
};

// Clusters `rows` (n x dim, row-major) into min(k, n) clusters. The seeding draws from
// RandomStream(stream_seed(seed, "kmeans")), so the result depends on the seed only. A cluster
// left empty by an iteration keeps its previous centre. `spherical`: the rows are unit vectors and
// each centre is renormalised after its update (spherical K-means, for features compared by
// cosine: for unit vectors the nearest centre is the one of largest cosine). Throws
// std::invalid_argument for n = 0 or k < 1.
KMeansResult kmeans(const std::vector<float>& rows, int dim, int k, uint64_t seed,
                    int max_iterations = 50, bool spherical = false);

}  // namespace gslift
