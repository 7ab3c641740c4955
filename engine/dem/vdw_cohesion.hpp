// Van der Waals cohesion, seed 000 ch. 5, combined with the contact force as Eq. 5.29:
// F(α) = A·R_eff/(6α²)·(1 − r_ss⁶/(60α⁶)) for α_min < α < α_cut, 0 beyond α_cut, and 0 for
// α ≤ α_min — in the gap below α_min and during overlap (α < 0), where Eq. 5.29 leaves
// only the spring. §5.3 chooses α_min at the point of zero force, α_min = r_ss/60^(1/6),
// so that the force falls continuously to zero there ("held constant" below it at that
// zero value). With r_ss = 0 the attraction instead stops abruptly at α_min.
// R_eff = R/2 between equal spheres (AR/(12α²), Eq. 5.28) and R at a wall (AR/(6α²), 5.21).
//
// Why not hold F(α_min) during overlap: a pull during overlap keeps a slow pair in
// contact, and Walton's latching spring (walton_normal.hpp) is lossless on its K2 line
// (unloading and reloading below the largest overlap dissipate nothing), so such a pair
// oscillates for ever. Without it, nothing holds a pair in overlap: it leaves contact every
// time, its history is forgotten, and each return is a fresh K1 loading that keeps e² of
// its energy — the decay to a negligible value of seed 000 Fig. 5.14–5.16.
#pragma once
#include <algorithm>
#include <string_view>

#include "engine/dem/contact_kinematics.hpp"
#include "engine/dem/sub_model.hpp"

namespace grainflow::dem {

struct VdwCohesion {
  static constexpr std::string_view kName = "vdw";
  static constexpr std::string_view kDescription =
      "van der Waals attraction of Eq. 5.29 (A, asperity radius, r_ss, α_min, α_cut; 0 at and below α_min)";
  // Hamaker constant A [J], asperity radius R [m] (0: use the particle radius), r_ss [m],
  // α_min and α_cut [m] (surface separations).
  struct Coeffs {
    double hamaker = 0.0;
    double vdw_radius = 0.0;
    double r_ss = 0.0;
    double alpha_min = 0.0;
    double alpha_cut = 0.0;
    static Coeffs mix(const Coeffs& a, const Coeffs& b) {
      return {mix_mean(a.hamaker, b.hamaker), mix_mean(a.vdw_radius, b.vdw_radius), mix_mean(a.r_ss, b.r_ss),
              mix_mean(a.alpha_min, b.alpha_min), mix_mean(a.alpha_cut, b.alpha_cut)};
    }
  };
  using Reads = TypeList<Coeffs>;
  static void validate(const auto& p, const CoeffCheck& c) {
    c.require(p.hamaker > 0.0, "hamaker", p.hamaker, "the Hamaker constant must be > 0 J");
    c.require(p.alpha_min > 0.0, "alpha_min", p.alpha_min, "the minimum separation must be > 0 m");
    c.require(p.alpha_cut > p.alpha_min, "alpha_cut", p.alpha_cut, "the cutoff must exceed alpha_min");
    c.require(p.r_ss >= 0.0, "r_ss", p.r_ss, "r_ss must be ≥ 0 m");
    c.require(p.vdw_radius >= 0.0, "vdw_radius", p.vdw_radius, "the asperity radius must be ≥ 0 m (0 = particle radius)");
  }

  static constexpr bool kNeedsRadius = true;  // reads ContactKinematics::r_eff
  static constexpr int kHistory = 0;
  struct Params {
    double hamaker = 0, asperity = 0, rss6 = 0, alpha_min = 0, alpha_cut = 0;
    bool operator==(const Params&) const = default;
  };
  static Params make(const auto& p, double /*m_eff_pair*/) {
    Params q;
    q.hamaker = p.hamaker;
    q.asperity = p.vdw_radius;
    q.rss6 = p.r_ss * p.r_ss * p.r_ss * p.r_ss * p.r_ss * p.r_ss;
    q.alpha_min = p.alpha_min;
    q.alpha_cut = p.alpha_cut;
    return q;
  }
  static double range(const Params& q) { return q.alpha_cut; }
  // Attractive magnitude [N] at surface separation `gap` = −delta (Eq. 5.29): zero at
  // and below α_min, overlap included.
  static double force(const Params& q, const ContactKinematics& k) {
    const double gap = -k.delta;
    if (gap >= q.alpha_cut || gap <= q.alpha_min) return 0.0;
    // Asperity radius R replaces the particle radius: R_eff = R/2 (pair) or R (wall).
    const double reff = q.asperity > 0.0 ? (k.wall ? q.asperity : 0.5 * q.asperity) : k.r_eff;
    return vdw_force(q.hamaker, reff, q.rss6, gap);
  }
  static double vdw_force(double A, double reff, double rss6, double a) {
    const double a2 = a * a, a6 = a2 * a2 * a2;
    return A * reff / (6.0 * a2) * (1.0 - rss6 / (60.0 * a6));
  }
};

struct NoCohesion {
  static constexpr std::string_view kName = "none";
  static constexpr std::string_view kDescription = "no cohesion";
  using Reads = TypeList<>;
  static void validate(const auto& /*p*/, const CoeffCheck& /*c*/) {}

  static constexpr bool kNeedsRadius = false;
  static constexpr int kHistory = 0;
  struct Params {
    bool operator==(const Params&) const = default;
  };
  static Params make(const auto& /*p*/, double /*m_eff_pair*/) { return {}; }
  static double range(const Params&) { return 0.0; }
  static double force(const Params&, const ContactKinematics&) { return 0.0; }
};

}  // namespace grainflow::dem
