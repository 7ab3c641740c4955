// What a DEM contact sub-model is made of (seed 000 §2.4–2.5, ch. 5; LAMMPS GRANULAR's
// gran_sub_mod_* pattern): the coefficient blocks it reads from the scene, their range
// check and mixing rule, and the type list that the tables of contact_models.hpp are.
#pragma once
#include <cmath>
#include <cstddef>
#include <string>

namespace grainflow::dem {

// A sub-model M is a struct of static members, next to its force formula:
//   kName, kDescription   its scene name and a one-line description (the schema's enum)
//   Reads                 TypeList of the coefficient blocks it reads: ContactParams
//                         derives from the union of all rows' blocks, so a new model
//                         with new coefficients declares them in its own header
//   validate(p, check)    range checks of what it reads, for the group being validated
//   Params, make(p, m_eff_pair), kHistory, force(...)   the evaluator of the contact loop
//   normal models:        collision_time(p, mu_red, m_eff_pair) and max_stiffness(p),
//                         which give the time step (Eq. 2.22–2.23) and stability limit
//   tangential models:    stiffness(p) of its spring for the stability limit (0: none)
//   optional:             template <class Other> static constexpr bool kCombinesWith,
//                         false for a partner it cannot be composed with
// p is a ContactParams, taken as `const auto&` because ContactParams is assembled from
// the blocks of every row and so is complete only after all sub-model headers.

template <class... T>
struct TypeList {
  static constexpr std::size_t size = sizeof...(T);
};

// Throws grainflow::Error "dem: <where>.<key> = <value> is not allowed; <allowed>" unless
// ok; where names the group being checked (e.g. "groups[0].contact").
struct CoeffCheck {
  const std::string& where;
  void require(bool ok, const char* key, double value, const char* allowed) const;
};

// The contact between two unlike groups takes the arithmetic mean of their values.
inline double mix_mean(double a, double b) { return 0.5 * (a + b); }
// A damping rate < 0 means "derive it" (from e, or from γn): it stays derived unless both
// groups give one.
inline double mix_rate(double a, double b) { return (a < 0.0 || b < 0.0) ? -1.0 : mix_mean(a, b); }

// The normal spring every normal model so far is given: k1 [N/m] (Walton's loading
// stiffness K1, Eq. 2.9; Hooke's kn) and the restitution coefficient e.
struct SpringCoeffs {
  double k1 = 0.0;
  double e = 1.0;
  static SpringCoeffs mix(const SpringCoeffs& a, const SpringCoeffs& b) {
    return {mix_mean(a.k1, b.k1), mix_mean(a.e, b.e)};
  }
  static void check_k1(const SpringCoeffs& s, const CoeffCheck& c) {
    c.require(std::isfinite(s.k1) && s.k1 > 0.0, "k1", s.k1, "the normal stiffness must be > 0 N/m");
  }
  static void check_e(const SpringCoeffs& s, const CoeffCheck& c) {
    c.require(s.e > 0.0 && s.e <= 1.0, "e", s.e, "the restitution coefficient must be in (0, 1]");
  }
};

// The tangential spring and Coulomb cap every tangential model so far is given: kt [N/m]
// (Walton's K0, Eq. 2.10; LAMMPS's kt) and the friction coefficient μ.
struct FrictionCoeffs {
  double kt = 0.0;
  double mu = 0.0;
  static FrictionCoeffs mix(const FrictionCoeffs& a, const FrictionCoeffs& b) {
    return {mix_mean(a.kt, b.kt), mix_mean(a.mu, b.mu)};
  }
  static void check(const FrictionCoeffs& f, const CoeffCheck& c) {
    c.require(std::isfinite(f.kt) && f.kt > 0.0, "kt", f.kt, "the tangential stiffness must be > 0 N/m");
    c.require(std::isfinite(f.mu) && f.mu >= 0.0, "mu", f.mu, "the friction coefficient must be ≥ 0");
  }
};

}  // namespace grainflow::dem
