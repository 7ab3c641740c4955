#include "engine/dem/time_step.hpp"

#include <cmath>
#include <numbers>

namespace grainflow::dem {

double walton_collision_time(double mu_red, double k1, double e) { return std::numbers::pi * e * std::sqrt(mu_red / k1); }

double walton_time_step(double m, double k1, double e, int n) { return walton_collision_time(0.5 * m, k1, e) / n; }

double hooke_collision_time(double mu_red, double kn, double gamma_n) {
  const double w2 = kn / mu_red - 0.25 * gamma_n * gamma_n;
  return w2 > 0.0 ? std::numbers::pi / std::sqrt(w2) : 0.0;
}

double leapfrog_stability_limit(double mu_red, double k) { return 2.0 * std::sqrt(mu_red / k); }

}  // namespace grainflow::dem
