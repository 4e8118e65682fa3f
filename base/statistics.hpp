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

// The two-sided 95% quantile of Student's t with df degrees of freedom (t_{0.975, df}): exact to
// three decimals from the table up to 30, then Cornish-Fisher's expansion around the normal
// quantile (error below 1e-4 from 30 on). NaN for df < 1.
inline double student_t_975(int df) {
  static const double table[31] = {NAN,   12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365,
                                   2.306, 2.262,  2.228, 2.201, 2.179, 2.160, 2.145, 2.131,
                                   2.120, 2.110,  2.101, 2.093, 2.086, 2.080, 2.074, 2.069,
                                   2.064, 2.060,  2.056, 2.052, 2.048, 2.045, 2.042};
  if (df < 1) return NAN;
  if (df <= 30) return table[df];
  const double z = 1.959963984540054, n = df;
  const double z3 = z * z * z, z5 = z3 * z * z, z7 = z5 * z * z;
  return z + (z3 + z) / (4 * n) + (5 * z5 + 16 * z3 + 3 * z) / (96 * n * n) +
         (3 * z7 + 19 * z5 + 17 * z3 - 15 * z) / (384 * n * n * n);
}

// A mean with its 95% confidence interval from Student's t (mean +- t * sd / sqrt(n)): what a
// paired comparison of two variants over the same rooms reports for the per-room differences.
// The interval is NaN with fewer than two values.
struct MeanInterval {
  size_t n = 0;
  double mean = NAN, low = NAN, high = NAN;
};
inline MeanInterval mean_interval_95(const std::vector<double>& v) {
  MeanInterval r;
  r.n = v.size();
  if (v.empty()) return r;
  const auto [m, sd] = mean_std(v);
  r.mean = m;
  if (v.size() < 2) return r;
  const double half =
      student_t_975(static_cast<int>(v.size() - 1)) * sd / std::sqrt(static_cast<double>(v.size()));
  r.low = m - half;
  r.high = m + half;
  return r;
}

}  // namespace gslift
