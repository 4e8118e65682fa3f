#include "report/timeline.hpp"

#include <algorithm>

namespace gslift::report {

std::vector<std::pair<double, int>> running_count(const std::vector<Interval>& intervals) {
  // Ends sort before starts at the same time: a node that starts as another ends did not run
  // beside it.
  std::vector<std::pair<double, int>> events;
  for (const auto& i : intervals)
    if (i.end > i.start) events.push_back({i.start, +1}), events.push_back({i.end, -1});
  std::sort(events.begin(), events.end());
  std::vector<std::pair<double, int>> steps;
  int running = 0;
  for (const auto& [t, delta] : events) {
    running += delta;
    if (!steps.empty() && steps.back().first == t)
      steps.back().second = running;
    else
      steps.push_back({t, running});
  }
  return steps;
}

int max_running(const std::vector<Interval>& intervals) {
  int best = 0;
  for (const auto& step : running_count(intervals)) best = std::max(best, step.second);
  return best;
}

}  // namespace gslift::report
