// Planted: report/ including a benchmark.
#include "bench/common/tsv.hpp"
