#include "report/pareto.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace gslift::report {

std::vector<size_t> pareto_front(const std::vector<ChartPoint>& points, bool lower_y_is_better) {
  const auto better_y = [&](double a, double b) { return lower_y_is_better ? a < b : a > b; };
  std::vector<size_t> order;
  for (size_t i = 0; i < points.size(); ++i)
    if (!std::isnan(points[i].x) && !std::isnan(points[i].y)) order.push_back(i);
  // By x, ties best y first: then a point is on the front exactly when its y beats every y
  // before it.
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    if (points[a].x != points[b].x) return points[a].x < points[b].x;
    return better_y(points[a].y, points[b].y);
  });
  std::vector<size_t> front;
  for (size_t i : order)
    if (front.empty() || better_y(points[i].y, points[front.back()].y)) front.push_back(i);
  return front;
}

}  // namespace gslift::report
