// The Pareto front of a speed-accuracy chart: the points that no other point beats on both axes.
#pragma once

#include <cstddef>
#include <vector>

namespace gslift::report {

struct ChartPoint {
  double x = 0, y = 0;
};

// Indices of the points not dominated by another, by ascending x. Smaller x is better (seconds,
// megabytes); larger y is better unless `lower_y_is_better`. A point is dominated by one that is
// at least as good on both axes and better on one. Points with a NaN coordinate are left out.
std::vector<size_t> pareto_front(const std::vector<ChartPoint>& points, bool lower_y_is_better);

}  // namespace gslift::report
