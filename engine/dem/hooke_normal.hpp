// Linear spring–dashpot normal force as LAMMPS pair_style gran/hooke/history:
// F_n = kn·δ + m_eff·γn·v_approach (may turn attractive at the end of a contact, as in
// LAMMPS without limit_damping). Used for side-by-side runs with LAMMPS/LIGGGHTS.
#pragma once
#include "engine/dem/contact_kinematics.hpp"
#include "engine/dem/contact_params.hpp"

namespace grainflow::dem {

struct HookeNormal {
  static constexpr bool kNeedsMass = true;  // reads ContactKinematics::m_eff
  static constexpr int kHistory = 0;
  struct Params {
    double kn = 0, gamma_n = 0;
    bool operator==(const Params&) const = default;
  };
  static Params make(const ContactParams& p, double m_eff_pair) {
    Params q;
    q.kn = p.k1;
    q.gamma_n = p.gamma_n >= 0.0 ? p.gamma_n : hooke_gamma_from_restitution(p.k1, p.e, m_eff_pair);
    return q;
  }
  // Always inlined: in the contact lanes it must become part of the SIMD loop.
  [[gnu::always_inline]] static double force(const Params& q, const ContactKinematics& k, double* /*h*/,
                                             bool /*update*/) {
    return q.kn * k.delta + k.m_eff * q.gamma_n * k.vn;
  }
};

}  // namespace grainflow::dem
