// The one-sample Kolmogorov–Smirnov statistic used by the stream-boundary tests to check
// sampled velocities against the analytic flux distributions of seed 003 §3.2.1.
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

namespace grainflow::test {

// D = sup_w |F_N(w) − F(w)| of the samples against the CDF F.
template <class Cdf>
double ks_statistic(std::vector<double> x, Cdf cdf) {
  std::sort(x.begin(), x.end());
  const double n = static_cast<double>(x.size());
  double d = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double f = cdf(x[i]);
    d = std::max({d, f - static_cast<double>(i) / n, static_cast<double>(i + 1) / n - f});
  }
  return d;
}

// Critical value of D at significance 0.001 for n samples (Kolmogorov's limit law,
// P(√n D > 1.9495) = 0.001; exact enough for n ≥ 100).
inline double ks_critical_001(std::size_t n) { return 1.9495 / std::sqrt(static_cast<double>(n)); }

}  // namespace grainflow::test
