// Cundall–Strack tangential spring with shear history, parameterised exactly as LAMMPS
// pair_style gran/hooke/history (kt, γt, μ, dampflag): the shear displacement accumulates
// v_t·dt, is rotated into the current tangent plane, and when |F_t| > μ|F_n| both the force
// and the stored displacement are rescaled (LAMMPS's rule, damping term included).
#pragma once
#include <cmath>
#include <string_view>

#include "engine/dem/contact_kinematics.hpp"
#include "engine/dem/hooke_normal.hpp"
#include "engine/dem/sub_model.hpp"

namespace grainflow::dem {

struct HistoryTangential {
  static constexpr std::string_view kName = "history";
  static constexpr std::string_view kDescription =
      "Cundall-Strack spring with shear history as LAMMPS gran/hooke/history (kt, γt, μ)";
  // γt [1/s] (force −m_eff·γt·v_t); < 0: γn/2 (LAMMPS's NULL). damp_flag is LAMMPS's
  // dampflag: false sets γt = 0.
  struct Coeffs {
    double gamma_t = -1.0;
    bool damp_flag = true;
    static Coeffs mix(const Coeffs& a, const Coeffs& b) {
      return {mix_rate(a.gamma_t, b.gamma_t), a.damp_flag && b.damp_flag};
    }
  };
  // The default γt is half of Hooke's γn, given or derived from e (LAMMPS's rule).
  using Reads = TypeList<FrictionCoeffs, Coeffs, SpringCoeffs, HookeNormal::Coeffs>;
  static void validate(const auto& p, const CoeffCheck& c) { FrictionCoeffs::check(p, c); }
  static double stiffness(const auto& p) { return p.kt; }

  static constexpr bool kNeedsMass = true;
  static constexpr int kHistory = 3;  // shear displacement vector [m]
  struct Params {
    double kt = 0, gamma_t = 0, mu = 0;
    bool operator==(const Params&) const = default;
  };
  static Params make(const auto& p, double m_eff_pair) {
    Params q;
    q.kt = p.kt;
    q.mu = p.mu;
    if (!p.damp_flag) {
      q.gamma_t = 0.0;
    } else if (p.gamma_t >= 0.0) {
      q.gamma_t = p.gamma_t;
    } else {
      q.gamma_t = 0.5 * HookeNormal::damping(p, m_eff_pair);
    }
    return q;
  }
  // fn: signed normal force of the normal sub-model; writes the tangential force on i.
  // Always inlined: in the contact lanes it must become part of the SIMD loop.
  [[gnu::always_inline]] static void force(const Params& q, const ContactKinematics& k, double fn, double* s,
                                           bool update, double ft[3]) {
    const double* n = k.n;
    const double* vt = k.vt;
    if (update) {
      s[0] += vt[0] * k.dt;
      s[1] += vt[1] * k.dt;
      s[2] += vt[2] * k.dt;
    }
    // |shear| is only tested against zero: its square gives the same answer without a sqrt.
    const double shrmag2 = s[0] * s[0] + s[1] * s[1] + s[2] * s[2];
    if (update) {
      const double rsht = s[0] * n[0] + s[1] * n[1] + s[2] * n[2];
      s[0] -= rsht * n[0];
      s[1] -= rsht * n[1];
      s[2] -= rsht * n[2];
    }
    const double md = k.m_eff * q.gamma_t;
    ft[0] = -(q.kt * s[0] + md * vt[0]);
    ft[1] = -(q.kt * s[1] + md * vt[1]);
    ft[2] = -(q.kt * s[2] + md * vt[2]);
    const double fs2 = ft[0] * ft[0] + ft[1] * ft[1] + ft[2] * ft[2];
    const double fmax = q.mu * std::fabs(fn);
    // Branch-free, so that a batch of contacts runs in SIMD lanes: the cap's sqrt and
    // division are computed for every contact and applied where |F_t| > μ|F_n|.
    const double fs = std::sqrt(fs2);
    const bool slide = fs > fmax;
    const bool rescale = slide & (shrmag2 != 0.0);  // else a sliding contact loses F_t
    const double ratio = fmax / fs;
    if (update) {
      const bool rescale_s = rescale & (q.kt > 0.0);
      const double c = md / q.kt;
      for (int a = 0; a < 3; ++a) s[a] = rescale_s ? ratio * (s[a] + c * vt[a]) - c * vt[a] : s[a];
    }
    for (int a = 0; a < 3; ++a) ft[a] = rescale ? ft[a] * ratio : (slide ? 0.0 : ft[a]);
  }
};

// Frictionless contacts: no tangential force, no history.
struct NoTangential {
  static constexpr std::string_view kName = "none";
  static constexpr std::string_view kDescription = "frictionless: no tangential force";
  using Reads = TypeList<>;
  static void validate(const auto& /*p*/, const CoeffCheck& /*c*/) {}
  static double stiffness(const auto& /*p*/) { return 0.0; }  // no spring, no limit

  static constexpr bool kNeedsMass = false;
  static constexpr int kHistory = 0;
  struct Params {
    bool operator==(const Params&) const = default;
  };
  static Params make(const auto& /*p*/, double /*m_eff_pair*/) { return {}; }
  static void force(const Params&, const ContactKinematics&, double, double*, bool, double ft[3]) {
    ft[0] = ft[1] = ft[2] = 0.0;
  }
};

}  // namespace grainflow::dem
