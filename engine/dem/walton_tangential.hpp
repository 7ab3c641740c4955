// Walton's incrementally slipping tangential friction, seed 000 §2.4 (Eq. 2.10–2.14):
// the old force is projected onto the new tangent plane keeping its magnitude (2.11),
// T* is rescaled with the normal force (2.12), the displacement parallel to the old force
// sees K_T from Eq. 2.10, the perpendicular part sees K0 (2.13), and |T| ≤ μ F_N.
#pragma once
#include <algorithm>
#include <cmath>
#include <string_view>

#include "engine/dem/contact_kinematics.hpp"
#include "engine/dem/sub_model.hpp"

namespace grainflow::dem {

// History: T (3, force on i), T*, F_N of the previous step, and the loading sense
// (+1 T increasing, −1 decreasing, 0 fresh contact). T is the magnitude of the tangential
// force; a reversal (change of sense) sets T* = T. When the decreasing branch brings T
// through zero the force points the other way and the next increment counts as a new
// reversal (T* = |T| ≈ 0): loading in the opposite direction restarts near the virgin
// curve. This is the 3D reading of Walton's 1D rule that needs no extra axis in history.
struct WaltonTangential {
  static constexpr std::string_view kName = "walton";
  static constexpr std::string_view kDescription =
      "Walton's incrementally slipping friction (K0 = kt, μ, γ; seed 000 §2.4)";
  // γ, the exponent of Eq. 2.10 (typically 1/3; 1 makes K_T linear in T).
  struct Coeffs {
    double walton_gamma = 1.0 / 3.0;
    static Coeffs mix(const Coeffs& a, const Coeffs& b) { return {mix_mean(a.walton_gamma, b.walton_gamma)}; }
  };
  using Reads = TypeList<FrictionCoeffs, Coeffs>;
  static void validate(const auto& p, const CoeffCheck& c) {
    FrictionCoeffs::check(p, c);
    c.require(p.walton_gamma > 0.0 && p.walton_gamma <= 10.0, "walton_gamma", p.walton_gamma,
              "the exponent γ of Eq. 2.10 must be in (0, 10]");
  }
  // K_T ≤ K0 (Eq. 2.10, 2.13): K0 is the stiffest tangential spring.
  static double stiffness(const auto& p) { return p.kt; }

  static constexpr bool kNeedsMass = false;  // never reads ContactKinematics::m_eff
  static constexpr int kHistory = 6;
  struct Params {
    double k0 = 0, mu = 0, gamma = 1.0 / 3.0;
    bool operator==(const Params&) const = default;
  };
  static Params make(const auto& p, double /*m_eff_pair*/) { return {p.kt, p.mu, p.walton_gamma}; }

  static void force(const Params& q, const ContactKinematics& k, double fn, double* h, bool update,
                    double ft[3]) {
    const double* n = k.n;
    const double mu_fn = q.mu * fn;
    if (!(fn > 0.0)) {  // latched (zero normal force): no friction, forget the history
      ft[0] = ft[1] = ft[2] = 0.0;
      if (update) std::fill(h, h + kHistory, 0.0);
      return;
    }
    // Eq. 2.11: project T_old onto the current tangent plane, keep its magnitude.
    double T[3] = {h[0], h[1], h[2]};
    const double told = std::sqrt(T[0] * T[0] + T[1] * T[1] + T[2] * T[2]);
    const double tn = T[0] * n[0] + T[1] * n[1] + T[2] * n[2];
    for (int a = 0; a < 3; ++a) T[a] -= tn * n[a];
    const double to = std::sqrt(T[0] * T[0] + T[1] * T[1] + T[2] * T[2]);
    double tmag = 0.0;
    if (to > 0.0) {
      const double s = told / to;
      for (int a = 0; a < 3; ++a) T[a] *= s;
      tmag = told;
    } else {
      T[0] = T[1] = T[2] = 0.0;
    }
    // Eq. 2.12: rescale T* with the normal force.
    double tstar = h[3];
    const double fn_old = h[4];
    if (fn_old > 0.0) tstar *= fn / fn_old;
    // Displacement that loads the spring in the direction of the force on i.
    const double ds[3] = {-k.vt[0] * k.dt, -k.vt[1] * k.dt, -k.vt[2] * k.dt};
    double dpar[3], dperp[3], s_par;
    if (tmag > 0.0) {
      const double inv = 1.0 / tmag;
      const double u[3] = {T[0] * inv, T[1] * inv, T[2] * inv};
      s_par = ds[0] * u[0] + ds[1] * u[1] + ds[2] * u[2];
      for (int a = 0; a < 3; ++a) {
        dpar[a] = s_par * u[a];
        dperp[a] = ds[a] - dpar[a];
      }
    } else {  // no previous force: the whole displacement is "parallel" loading
      s_par = 1.0;
      for (int a = 0; a < 3; ++a) {
        dpar[a] = ds[a];
        dperp[a] = 0.0;
      }
    }
    const double sense = s_par >= 0.0 ? 1.0 : -1.0;
    const double old_sense = h[5];
    if (old_sense != 0.0 && sense != old_sense) tstar = tmag;  // reversal
    // Eq. 2.10
    double x;
    if (sense > 0.0) {
      const double den = mu_fn - tstar;
      x = den > 0.0 ? 1.0 - (tmag - tstar) / den : 0.0;
    } else {
      x = 1.0 - (tstar - tmag) / (mu_fn + tstar);
    }
    x = std::clamp(x, 0.0, 1.0);
    const double kt = q.gamma == 1.0 ? q.k0 * x : q.k0 * std::pow(x, q.gamma);
    // Eq. 2.13–2.14
    for (int a = 0; a < 3; ++a) ft[a] = T[a] + kt * dpar[a] + q.k0 * dperp[a];
    const double fm = std::sqrt(ft[0] * ft[0] + ft[1] * ft[1] + ft[2] * ft[2]);
    if (fm > mu_fn) {  // sliding
      const double s = mu_fn / fm;
      for (int a = 0; a < 3; ++a) ft[a] *= s;
      tstar = std::min(tstar, mu_fn);
    }
    if (update) {
      h[0] = ft[0];
      h[1] = ft[1];
      h[2] = ft[2];
      h[3] = tstar;
      h[4] = fn;
      h[5] = sense;
    }
  }
};

}  // namespace grainflow::dem
