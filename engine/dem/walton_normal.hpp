// Walton's partially latching spring, the normal contact force of seed 000 §2.4
// (Eq. 2.1–2.9): loading F = K1·α, unloading F = K2·(α − α0), e = sqrt(K1/K2).
#pragma once
#include <algorithm>

#include "engine/dem/contact_kinematics.hpp"
#include "engine/dem/contact_params.hpp"

namespace grainflow::dem {

// History: α0, the overlap at which the unloading line reaches zero force. It only grows
// (α0 = α_max(1 − K1/K2)), so min(K1·α, K2·(α − α0)) picks the loading line for α ≥ α_max
// and the unloading line below it; force is clamped at zero (latched) for α < α0.
struct WaltonNormal {
  static constexpr bool kNeedsMass = false;  // never reads ContactKinematics::m_eff
  static constexpr int kHistory = 1;
  struct Params {
    double k1 = 0, k2 = 0, unload_ratio = 0;  // unload_ratio = 1 − K1/K2
    bool operator==(const Params&) const = default;
  };
  static Params make(const ContactParams& p, double /*m_eff_pair*/) {
    Params q;
    q.k1 = p.k1;
    q.k2 = p.k1 / (p.e * p.e);
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
