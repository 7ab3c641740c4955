// Pins the collision rule of seed 003 §3.4 (Eq. 3.49–3.69): conservation laws, the
// head-on energy loss, and the sticking vs sliding branches with the formal coefficient.
#include <cmath>

#include <gtest/gtest.h>

#include "engine/ed/collision_rule.hpp"

namespace ed = grainflow::ed;

namespace {
struct Pair {
  double x1 = 0.0, y1 = 0.0, x2 = 1.0, y2 = 0.0;  // contact at distance 1
  double vx1, vy1, vx2, vy2, w1 = 0.0, w2 = 0.0;
  double m1 = 1.0, m2 = 1.0, R1 = 0.5, R2 = 0.5;
};
struct After {
  double vx1, vy1, vx2, vy2, w1, w2;
  bool sliding;
};
After collide(const Pair& p, const ed::CollisionParams& c) {
  const auto J = ed::collision_impulse(p.x1 - p.x2, p.y1 - p.y2, p.vx1 - p.vx2, p.vy1 - p.vy2, p.R1, p.R2,
                                       p.w1, p.w2, p.m1, p.m2, c);
  return {p.vx1 + J.jx / p.m1, p.vy1 + J.jy / p.m1, p.vx2 - J.jx / p.m2, p.vy2 - J.jy / p.m2,
          p.w1 + J.dw1, p.w2 + J.dw2, J.sliding};
}
double energy(const Pair& p, double vx1, double vy1, double vx2, double vy2, double w1, double w2, double q) {
  return 0.5 * p.m1 * (vx1 * vx1 + vy1 * vy1) + 0.5 * p.m2 * (vx2 * vx2 + vy2 * vy2) +
         0.5 * q * p.m1 * p.R1 * p.R1 * w1 * w1 + 0.5 * q * p.m2 * p.R2 * p.R2 * w2 * w2;
}
// Angular momentum about the contact point c (z component): I ω + m (r − c) × v.
double ang_mom(const Pair& p, double vx1, double vy1, double vx2, double vy2, double w1, double w2, double q) {
  const double cx = p.x1 + (p.x2 - p.x1) * p.R1 / (p.R1 + p.R2), cy = p.y1 + (p.y2 - p.y1) * p.R1 / (p.R1 + p.R2);
  return q * p.m1 * p.R1 * p.R1 * w1 + q * p.m2 * p.R2 * p.R2 * w2 +
         p.m1 * ((p.x1 - cx) * vy1 - (p.y1 - cy) * vx1) + p.m2 * ((p.x2 - cx) * vy2 - (p.y2 - cy) * vx2);
}
}  // namespace

TEST(CollisionRule, SmoothElasticConservesMomentumAndEnergy) {
  Pair p;
  p.x2 = 0.6; p.y2 = 0.8;  // oblique contact
  p.vx1 = 0.7; p.vy1 = 0.3; p.vx2 = -0.2; p.vy2 = -0.5; p.m2 = 2.5; p.R2 = 0.5;
  const auto a = collide(p, ed::CollisionParams{});
  EXPECT_NEAR(p.m1 * a.vx1 + p.m2 * a.vx2, p.m1 * p.vx1 + p.m2 * p.vx2, 1e-14);
  EXPECT_NEAR(p.m1 * a.vy1 + p.m2 * a.vy2, p.m1 * p.vy1 + p.m2 * p.vy2, 1e-14);
  EXPECT_NEAR(energy(p, a.vx1, a.vy1, a.vx2, a.vy2, 0, 0, 0.5), energy(p, p.vx1, p.vy1, p.vx2, p.vy2, 0, 0, 0.5), 1e-14);
  // Tangential relative velocity untouched for smooth disks; normal one reversed (Eq. 3.52).
  const double nx = -0.6, ny = -0.8;
  EXPECT_NEAR((a.vx1 - a.vx2) * nx + (a.vy1 - a.vy2) * ny, -((p.vx1 - p.vx2) * nx + (p.vy1 - p.vy2) * ny), 1e-14);
  EXPECT_NEAR(-(a.vx1 - a.vx2) * ny + (a.vy1 - a.vy2) * nx, -(p.vx1 - p.vx2) * ny + (p.vy1 - p.vy2) * nx, 1e-14);
}

TEST(CollisionRule, HeadOnEnergyLoss) {
  // Equal masses, relative normal speed v_n = 1.5: loss (1 − e²)/4 · m · v_n².
  for (double e : {0.0, 0.5, 0.87, 1.0}) {
    Pair p;
    p.vx1 = 1.0; p.vy1 = 0.0; p.vx2 = -0.5; p.vy2 = 0.0;
    ed::CollisionParams c;
    c.e = e;
    const auto a = collide(p, c);
    const double loss = energy(p, p.vx1, p.vy1, p.vx2, p.vy2, 0, 0, 0.5) - energy(p, a.vx1, a.vy1, a.vx2, a.vy2, 0, 0, 0.5);
    EXPECT_NEAR(loss, (1.0 - e * e) / 4.0 * 1.0 * 1.5 * 1.5, 1e-14) << "e = " << e;
    EXPECT_NEAR(a.vx1 - a.vx2, -e * 1.5, 1e-14);
    EXPECT_NEAR(a.vx1 + a.vx2, 0.5, 1e-14);
  }
}

TEST(CollisionRule, StickingBranchRestoresTangentialVelocity) {
  // Small tangential slip against a large normal speed: sticking, g_t' = −e_t g_t (Eq. 3.63).
  Pair p;
  p.vx1 = 1.0; p.vy1 = 0.1; p.vx2 = 0.0; p.vy2 = 0.0; p.w1 = 0.2;
  ed::CollisionParams c{0.9, 0.4, 0.5, 0.5};
  const auto a = collide(p, c);
  EXPECT_FALSE(a.sliding);
  // n̂ = (−1, 0); g_t is the y component of g = c − (R1ω1 + R2ω2) ẑ×n̂, ẑ×n̂ = (0, −1).
  const double gt = (p.vy1 - p.vy2) + (p.R1 * p.w1 + p.R2 * p.w2);
  const double gt_after = (a.vy1 - a.vy2) + (p.R1 * a.w1 + p.R2 * a.w2);
  EXPECT_NEAR(gt_after, -0.4 * gt, 1e-14);
  EXPECT_NEAR(a.vx1 - a.vx2, -0.9, 1e-14);
  EXPECT_NEAR(ang_mom(p, a.vx1, a.vy1, a.vx2, a.vy2, a.w1, a.w2, 0.5), ang_mom(p, p.vx1, p.vy1, p.vx2, p.vy2, p.w1, p.w2, 0.5), 1e-14);
}

TEST(CollisionRule, SlidingBranchIsCoulomb) {
  // Large slip: |j_t| = μ |j_n| = μ (1 + e) M |g_n| (Eq. 3.66), opposite to g_t.
  Pair p;
  p.vx1 = 0.2; p.vy1 = 1.0; p.vx2 = 0.0; p.vy2 = 0.0;
  const double e = 0.97, mu = 0.09;
  ed::CollisionParams c{e, 0.44, mu, 0.5};  // Fig. 3.11's parameters
  const auto a = collide(p, c);
  EXPECT_TRUE(a.sliding);
  const double M = 0.5;
  const double jt = p.m1 * (a.vy1 - p.vy1);
  EXPECT_NEAR(jt, -mu * (1.0 + e) * M * 0.2, 1e-14);
  // Formal coefficient e_t1 (Eq. 3.68) reproduces the same impulse through Eq. 3.64.
  const double et1 = -1.0 + mu * (1.0 + e) * 3.0 * 0.2 / 1.0;
  EXPECT_LT(et1, 0.44);
  EXPECT_NEAR(jt, -M * (0.5 / 1.5) * (1.0 + et1) * 1.0, 1e-14);
  EXPECT_NEAR(ang_mom(p, a.vx1, a.vy1, a.vx2, a.vy2, a.w1, a.w2, 0.5), ang_mom(p, p.vx1, p.vy1, p.vx2, p.vy2, p.w1, p.w2, 0.5), 1e-14);
  // Linear momentum conserved, energy lost.
  EXPECT_NEAR(a.vy1 + a.vy2, 1.0, 1e-14);
  EXPECT_LT(energy(p, a.vx1, a.vy1, a.vx2, a.vy2, a.w1, a.w2, 0.5), energy(p, p.vx1, p.vy1, p.vx2, p.vy2, 0, 0, 0.5));
}

TEST(CollisionRule, PerfectlyRoughElasticConservesEnergy) {
  // e = 1, e_t = 1, no sliding (μ = ∞): translational + rotational energy conserved.
  Pair p;
  p.x2 = 0.8; p.y2 = -0.6;
  p.vx1 = 0.5; p.vy1 = -0.3; p.vx2 = -0.4; p.vy2 = 0.6; p.w1 = 1.3; p.w2 = -0.7;
  ed::CollisionParams c{1.0, 1.0, INFINITY, 0.5};
  const auto a = collide(p, c);
  EXPECT_FALSE(a.sliding);
  EXPECT_NEAR(energy(p, a.vx1, a.vy1, a.vx2, a.vy2, a.w1, a.w2, 0.5), energy(p, p.vx1, p.vy1, p.vx2, p.vy2, p.w1, p.w2, 0.5), 1e-13);
  EXPECT_NEAR(ang_mom(p, a.vx1, a.vy1, a.vx2, a.vy2, a.w1, a.w2, 0.5), ang_mom(p, p.vx1, p.vy1, p.vx2, p.vy2, p.w1, p.w2, 0.5), 1e-14);
}

TEST(CollisionRule, FormalCoefficientIsMinimum) {
  // Scan the impact angle: the tangential impulse equals Eq. 3.64 with min(e_t1, e_t).
  const double e = 0.97, et = 0.44, mu = 0.09, q = 0.5, M = 0.5;
  int sliding = 0, sticking = 0;
  for (int k = 1; k < 40; ++k) {
    const double gt = 0.05 * k;
    Pair p;
    p.vx1 = 1.0; p.vy1 = gt; p.vx2 = 0.0; p.vy2 = 0.0;
    const auto a = collide(p, ed::CollisionParams{e, et, mu, q});
    const double et1 = -1.0 + mu * (1.0 + e) * (1.0 + 1.0 / q) * 1.0 / gt;
    const double expect = -M * q / (1.0 + q) * (1.0 + std::min(et1, et)) * gt;
    EXPECT_NEAR(p.m1 * (a.vy1 - p.vy1), expect, 1e-14) << "g_t = " << gt;
    (a.sliding ? sliding : sticking)++;
  }
  EXPECT_GT(sliding, 0);
  EXPECT_GT(sticking, 0);
}
