// Summaries over seeds: what every benchmark and `gslift sweep` report.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace gslift {

// Mean and sample standard deviation (n - 1); NaN for an empty series, std 0 for one value.
inline std::pair<double, double> mean_std(const std::vector<double>& v) {
  if (v.empty()) return {NAN, NAN};
  double m = 0;
  for (double x : v) m += x;
  m /= static_cast<double>(v.size());
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return {m, v.size() > 1 ? std::sqrt(s / static_cast<double>(v.size() - 1)) : 0.0};
}

// Median (the mean of the two middle values for an even count); NaN for an empty series.
inline double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace gslift
