// When nodes ran at once: the run record gives each node's start and end (seconds since the run
// started, on the flow graph's clock); the timeline draws them and this counts how many ran at
// once.
#pragma once

#include <utility>
#include <vector>

namespace gslift::report {

struct Interval {
  double start = 0, end = 0;
};

// The number of intervals running over time, as steps (t, count from t on), times ascending, the
// last step 0. An interval covers [start, end); empty ones (end <= start) never count.
std::vector<std::pair<double, int>> running_count(const std::vector<Interval>& intervals);

// The most intervals running at one time.
int max_running(const std::vector<Interval>& intervals);

}  // namespace gslift::report
