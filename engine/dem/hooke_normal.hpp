// Linear spring–dashpot normal force as LAMMPS pair_style gran/hooke/history, for
// side-by-side runs with LAMMPS/LIGGGHTS (not in seed 000; its collision time π/ω_d takes
// the place of Eq. 2.22 in the time step of §2.5): F_n = kn·δ + m_eff·γn·v_approach (may
// turn attractive at the end of a contact, as in LAMMPS without limit_damping).
#pragma once
#include <cmath>
#include <numbers>
#include <string_view>

#include "engine/dem/contact_kinematics.hpp"
#include "engine/dem/sub_model.hpp"

namespace grainflow::dem {

// LAMMPS-style γn [1/s] that gives restitution e for a linear spring kn between two
// bodies of reduced mass m_eff: γn = −2 ln e · ω0 / sqrt(π² + ln² e), ω0 = sqrt(kn/m_eff).
inline double hooke_gamma_from_restitution(double kn, double e, double m_eff) {
  const double le = std::log(e);
  const double w0 = std::sqrt(kn / m_eff);
  return -2.0 * le * w0 / std::sqrt(std::numbers::pi * std::numbers::pi + le * le);
}
// Linear spring–dashpot contact duration π/ω_d, ω_d = sqrt(kn/μ − γn²/4); 0 when
// overdamped (no rebound, so no collision time to resolve).
inline double hooke_collision_time(double mu_red, double kn, double gamma_n) {
  const double w2 = kn / mu_red - 0.25 * gamma_n * gamma_n;
  return w2 > 0.0 ? std::numbers::pi / std::sqrt(w2) : 0.0;
}

struct HookeNormal {
  static constexpr std::string_view kName = "hooke";
  static constexpr std::string_view kDescription =
      "linear spring-dashpot as LAMMPS gran/hooke/history (kn = k1, γn or e)";
  // γn [1/s] (force −m_eff·γn·v_n); < 0 derives it from e for a pair of two equal
  // particles of the group, exactly as LAMMPS users do.
  struct Coeffs {
    double gamma_n = -1.0;
    static Coeffs mix(const Coeffs& a, const Coeffs& b) { return {mix_rate(a.gamma_n, b.gamma_n)}; }
  };
  using Reads = TypeList<SpringCoeffs, Coeffs>;
  static void validate(const auto& p, const CoeffCheck& c) {
    SpringCoeffs::check_k1(p, c);
    if (p.gamma_n < 0.0) SpringCoeffs::check_e(p, c);  // e only matters when γn is derived
    c.require(std::isfinite(p.gamma_n) && (p.gamma_n >= 0.0 || p.gamma_n == -1.0), "gamma_n", p.gamma_n,
              "γn must be ≥ 0 1/s (or −1 to derive it from e)");
  }
  // γn as given, or derived from e for the pair's reduced mass m_eff_pair.
  static double damping(const auto& p, double m_eff_pair) {
    return p.gamma_n >= 0.0 ? p.gamma_n : hooke_gamma_from_restitution(p.k1, p.e, m_eff_pair);
  }
  static double collision_time(const auto& p, double mu_red, double m_eff_pair) {
    return hooke_collision_time(mu_red, p.k1, damping(p, m_eff_pair));
  }
  static double max_stiffness(const auto& p) { return p.k1; }

  static constexpr bool kNeedsMass = true;  // reads ContactKinematics::m_eff
  static constexpr int kHistory = 0;
  struct Params {
    double kn = 0, gamma_n = 0;
    bool operator==(const Params&) const = default;
  };
  static Params make(const auto& p, double m_eff_pair) {
    Params q;
    q.kn = p.k1;
    q.gamma_n = damping(p, m_eff_pair);
    return q;
  }
  // Always inlined: in the contact lanes it must become part of the SIMD loop.
  [[gnu::always_inline]] static double force(const Params& q, const ContactKinematics& k, double* /*h*/,
                                             bool /*update*/) {
    return q.kn * k.delta + k.m_eff * q.gamma_n * k.vn;
  }
};

}  // namespace grainflow::dem
