// The one-sample Kolmogorov–Smirnov statistic used by the stream-boundary tests to check
// sampled velocities against the analytic flux distributions of seed 003 §3.2.1, and by
// the thermostat tests against Maxwell–Boltzmann.
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

// P(D_n ≥ d) under the null hypothesis: Kolmogorov's limit law Q(λ) = 2 Σ (−1)^(k−1)
// exp(−2k²λ²) with Stephens' small-sample correction λ = (√n + 0.12 + 0.11/√n) d.
inline double ks_p_value(std::size_t n, double d) {
  const double sn = std::sqrt(static_cast<double>(n));
  const double lambda = (sn + 0.12 + 0.11 / sn) * d;
  if (lambda < 0.2) return 1.0;
  double q = 0.0;
  for (int k = 1; k <= 100; ++k) {
    const double term = std::exp(-2.0 * k * k * lambda * lambda);
    q += (k % 2 ? 2.0 : -2.0) * term;
    if (term < 1e-16) break;
  }
  return std::clamp(q, 0.0, 1.0);
}

}  // namespace grainflow::test
