// Van der Waals cohesion, seed 000 ch. 5 (Eq. 5.28, 5.21 combined as Eq. 5.29):
// F(α) = A·R_eff/(6α²)·(1 − r_ss⁶/(60α⁶)) for α_min < α < α_cut, F(α_min) for α ≤ α_min
// (also during overlap, where the normal model acts as well), 0 beyond α_cut.
// R_eff = R/2 between equal spheres (AR/(12α²), Eq. 5.28) and R at a wall (AR/(6α²), 5.21).
#pragma once
#include <algorithm>

#include "engine/dem/contact_kinematics.hpp"
#include "engine/dem/contact_params.hpp"

namespace grainflow::dem {

struct VdwCohesion {
  static constexpr bool kNeedsRadius = true;  // reads ContactKinematics::r_eff
  static constexpr int kHistory = 0;
  struct Params {
    double hamaker = 0, asperity = 0, rss6 = 0, alpha_min = 0, alpha_cut = 0;
    bool operator==(const Params&) const = default;
  };
  static Params make(const ContactParams& p, double) {
    Params q;
    q.hamaker = p.hamaker;
    q.asperity = p.vdw_radius;
    q.rss6 = p.r_ss * p.r_ss * p.r_ss * p.r_ss * p.r_ss * p.r_ss;
    q.alpha_min = p.alpha_min;
    q.alpha_cut = p.alpha_cut;
    return q;
  }
  static double range(const Params& q) { return q.alpha_cut; }
  // Attractive magnitude [N] at surface separation `gap` = −delta.
  static double force(const Params& q, const ContactKinematics& k) {
    const double gap = -k.delta;
    if (gap >= q.alpha_cut) return 0.0;
    // Asperity radius R replaces the particle radius: R_eff = R/2 (pair) or R (wall).
    const double reff = q.asperity > 0.0 ? (k.wall ? q.asperity : 0.5 * q.asperity) : k.r_eff;
    return vdw_force(q.hamaker, reff, q.rss6, std::max(gap, q.alpha_min));
  }
  static double vdw_force(double A, double reff, double rss6, double a) {
    const double a2 = a * a, a6 = a2 * a2 * a2;
    return A * reff / (6.0 * a2) * (1.0 - rss6 / (60.0 * a6));
  }
};

struct NoCohesion {
  static constexpr bool kNeedsRadius = false;
  static constexpr int kHistory = 0;
  struct Params {
    bool operator==(const Params&) const = default;
  };
  static Params make(const ContactParams&, double) { return {}; }
  static double range(const Params&) { return 0.0; }
  static double force(const Params&, const ContactKinematics&) { return 0.0; }
};

}  // namespace grainflow::dem
