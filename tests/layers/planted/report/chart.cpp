// Planted: report/ including a benchmark.
#include "bench/common/svg.hpp"
