// The binary collision rule of seed 003 §3.4 (Eq. 3.49–3.69) for 2D disks: normal
// restitution e, and for rough disks tangential restitution e_t with Coulomb sliding
// (friction μ), the formal tangential coefficient being min(e_t1, e_t) (Fig. 3.11).
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>

namespace grainflow::ed {

struct CollisionParams {
  double e = 1.0;    // normal restitution, [0, 1] (Eq. 3.52)
  double e_t = 1.0;  // tangential restitution for sticking contacts, [−1, 1] (Eq. 3.63)
  double mu = 0.0;   // Coulomb friction; 0 = smooth disks (no tangential impulse)
  double q = 0.5;    // I = q m (σ/2)^2, q = 1/2 for uniform disks (Eq. 3.59)
  bool smooth() const { return mu == 0.0; }
};

// Result of one collision: impulse j exerted by 2 on 1 (Eq. 3.50) and the changes of the
// angular velocities (z components; Eq. 3.60).
struct CollisionImpulse {
  double jx = 0.0, jy = 0.0;
  double dw1 = 0.0, dw2 = 0.0;
  bool sliding = false;  // rough disks: Coulomb branch (e_t1 < e_t) taken
};

// rx, ry: r = r1 − r2 at contact; cx, cy: c = c1 − c2 (Eq. 3.49); R = σ/2; w = ω_z.
// Velocities after: c1' = c1 + j/m1, c2' = c2 − j/m2, ω1' = ω1 + dw1, ω2' = ω2 + dw2.
// M: the reduced mass m1 m2 / (m1 + m2), given separately so that m2 = ∞ has a limit.
inline CollisionImpulse collision_impulse_reduced(double rx, double ry, double cx, double cy, double R1,
                                                  double R2, double w1, double w2, double m1, double m2,
                                                  double M, const CollisionParams& p) {
  CollisionImpulse out;
  const double r2 = rx * rx + ry * ry;
  const double cr = cx * rx + cy * ry;
  // Eq. 3.54 with c_n from Eq. 3.55 (no square root needed for smooth disks).
  const double jn = -(1.0 + p.e) * M * cr / r2;
  out.jx = jn * rx;
  out.jy = jn * ry;
  if (p.smooth()) return out;

  const double inv_r = 1.0 / std::sqrt(r2);
  const double nx = rx * inv_r, ny = ry * inv_r;
  // Eq. 3.56 in 2D: (ω ẑ) × n̂ = ω (−n_y, n_x).
  const double s = R1 * w1 + R2 * w2;
  const double gx = cx + s * ny, gy = cy - s * nx;
  const double gn = gx * nx + gy * ny;
  const double gtx = gx - gn * nx, gty = gy - gn * ny;
  const double gt = std::sqrt(gtx * gtx + gty * gty);
  if (gt == 0.0) return out;
  const double q = p.q;
  // Eq. 3.68 written with cot γ = −|g_n|/|g_t|; sliding when it lies below e_t (Eq. 3.69).
  const double et1 = -1.0 + p.mu * (1.0 + p.e) * (1.0 + 1.0 / q) * std::abs(gn) / gt;
  const double et = std::min(p.e_t, et1);
  out.sliding = et1 < p.e_t;
  const double k = -M * q / (1.0 + q) * (1.0 + et);  // Eq. 3.64
  const double jtx = k * gtx, jty = k * gty;
  out.jx += jtx;
  out.jy += jty;
  // Eq. 3.58/3.60: I_i Δω_i = −(σ_i/2) (n̂ × j_t)_z, I_i = q m_i R_i^2.
  const double nxj = nx * jty - ny * jtx;
  out.dw1 = -nxj / (q * m1 * R1);
  out.dw2 = -nxj / (q * m2 * R2);
  return out;
}

inline CollisionImpulse collision_impulse(double rx, double ry, double cx, double cy, double R1,
                                          double R2, double w1, double w2, double m1, double m2,
                                          const CollisionParams& p) {
  return collision_impulse_reduced(rx, ry, cx, cy, R1, R2, w1, w2, m1, m2, m1 * m2 / (m1 + m2), p);
}

// Disk 2 infinitely heavy (the outlet filter's frozen disks, seed 003 §3.3, Fig. 3.8): the
// limit m2 → ∞ taken by hand (M = m1, no change of disk 2), so no ∞/∞ appears. Disk 1
// reflects in disk 2's frame.
inline CollisionImpulse collision_impulse_heavy(double rx, double ry, double cx, double cy, double R1,
                                                double R2, double w1, double w2, double m1,
                                                const CollisionParams& p) {
  CollisionImpulse out = collision_impulse_reduced(rx, ry, cx, cy, R1, R2, w1, w2, m1,
                                                   std::numeric_limits<double>::infinity(), m1, p);
  out.dw2 = 0.0;
  return out;
}

}  // namespace grainflow::ed
