// Walton's partially latching spring, the normal contact force of seed 000 §2.4
// (Eq. 2.1–2.9): loading F = K1·α, unloading F = K2·(α − α0), e = sqrt(K1/K2); and its
// collision time, which sets the time step (§2.5, Eq. 2.22–2.23).
#pragma once
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string_view>

#include "engine/dem/contact_kinematics.hpp"
#include "engine/dem/sub_model.hpp"

namespace grainflow::dem {

// Eq. 2.21–2.22: duration of a Walton collision for reduced mass mu_red, taken from the
// restoration (unloading) spring, the stiffer one: π·sqrt(μ/K2) = π·e·sqrt(μ/K1).
inline double walton_collision_time(double mu_red, double k1, double e) {
  return std::numbers::pi * e * std::sqrt(mu_red / k1);
}
// Eq. 2.23 with the reduced mass of two equal particles of mass m: π e sqrt(m/(2K1))/n.
inline double walton_time_step(double m, double k1, double e, int n) { return walton_collision_time(0.5 * m, k1, e) / n; }

// History: α0, the overlap at which the unloading line reaches zero force. It only grows
// (α0 = α_max(1 − K1/K2)), so min(K1·α, K2·(α − α0)) picks the loading line for α ≥ α_max
// and the unloading line below it; force is clamped at zero (latched) for α < α0.
struct WaltonNormal {
  static constexpr std::string_view kName = "walton";
  static constexpr std::string_view kDescription =
      "Walton's partially latching spring (K1 = k1, K2 = k2 or K1/e², seed 000 §2.4)";
  // K2 [N/m], the unloading (restoration) spring of Eq. 2.1; 0 derives it from e as
  // K2 = K1/e² (Eq. 2.9). Given, it replaces e: the restitution is then sqrt(K1/K2).
  struct Coeffs {
    double k2 = 0.0;
    static Coeffs mix(const Coeffs& a, const Coeffs& b) {
      return {(a.k2 > 0.0 && b.k2 > 0.0) ? mix_mean(a.k2, b.k2) : 0.0};  // derived unless both give it
    }
  };
  using Reads = TypeList<SpringCoeffs, Coeffs>;
  static void validate(const auto& p, const CoeffCheck& c) {
    SpringCoeffs::check_k1(p, c);
    if (p.k2 == 0.0) SpringCoeffs::check_e(p, c);  // e only matters when K2 is derived
    c.require(p.k2 == 0.0 || (std::isfinite(p.k2) && p.k2 >= p.k1), "k2", p.k2,
              "K2 must be ≥ K1 (e = sqrt(K1/K2) ≤ 1), or 0 to derive it from e");
  }
  // K2 = k2, or K1/e² (Eq. 2.9): never softer than K1, so the stiffest.
  static double unloading_stiffness(const auto& p) { return p.k2 > 0.0 ? p.k2 : p.k1 / (p.e * p.e); }
  // Eq. 2.21: π sqrt(μ/K2); with K2 derived this is Eq. 2.22's π e sqrt(μ/K1).
  static double collision_time(const auto& p, double mu_red, double /*m_eff_pair*/) {
    if (p.k2 > 0.0) return std::numbers::pi * std::sqrt(mu_red / p.k2);
    return walton_collision_time(mu_red, p.k1, p.e);
  }
  static double max_stiffness(const auto& p) { return unloading_stiffness(p); }

  static constexpr bool kNeedsMass = false;  // never reads ContactKinematics::m_eff
  static constexpr int kHistory = 1;
  struct Params {
    double k1 = 0, k2 = 0, unload_ratio = 0;  // unload_ratio = 1 − K1/K2
    bool operator==(const Params&) const = default;
  };
  static Params make(const auto& p, double /*m_eff_pair*/) {
    Params q;
    q.k1 = p.k1;
    q.k2 = unloading_stiffness(p);
    q.unload_ratio = 1.0 - q.k1 / q.k2;
    return q;
  }
  // Normal force magnitude (repulsive > 0) for delta > 0.
  static double force(const Params& q, const ContactKinematics& k, double* h, bool update) {
    const double a = k.delta;
    const double loading = q.k1 * a;
    const double unloading = q.k2 * (a - h[0]);
    if (loading <= unloading) {
      if (update) h[0] = a * q.unload_ratio;  // new maximum overlap
      return loading;
    }
    return std::max(0.0, unloading);
  }
};

}  // namespace grainflow::dem
