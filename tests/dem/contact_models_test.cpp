// Contact sub-models of the DEM engine against hand-computed values: Walton's latching
// spring (seed 000 Eq. 2.1–2.9), Walton's tangential model (Eq. 2.10–2.14), the LAMMPS
// gran/hooke/history law, and van der Waals cohesion (Eq. 5.28, 5.21, 5.29).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "engine/dem/contact_law.hpp"
#include "engine/dem/time_step.hpp"
#include "engine/dem/vdw_cohesion.hpp"

using namespace grainflow::dem;

namespace {

std::unique_ptr<ContactLaw> law_of(const ContactModelSpec& spec, const ContactParams& p, double meff = 1.0) {
  std::array<ContactParams, 9> per;
  per.fill(p);
  std::array<double, 9> m;
  m.fill(meff);
  return make_contact_law(spec, per, m);
}

ContactKinematics kin(double delta, double nx = 1, double ny = 0, double nz = 0) {
  ContactKinematics k{};
  k.n[0] = nx;
  k.n[1] = ny;
  k.n[2] = nz;
  k.delta = delta;
  k.m_eff = 1.0;
  k.r_eff = 1.0;
  k.dt = 1.0;
  return k;
}

}  // namespace

TEST(WaltonNormal, LoadUnloadReloadCycleMatchesHandValues) {
  ContactParams p;
  p.k1 = 100.0;
  p.e = 0.5;  // K2 = K1/e² = 400, α0 = α_max (1 − K1/K2) = 0.75 α_max
  auto law = law_of({NormalKind::Walton, TangentialKind::None, CohesionKind::None}, p);
  std::vector<double> h(law->history_size(), 0.0);
  ASSERT_EQ(law->history_size(), 1);
  struct Step {
    double alpha, force;
  };
  const Step steps[] = {
      {1.0e-3, 0.100},   // loading K1 α
      {2.0e-3, 0.200},   // loading, α_max = 2e-3 → α0 = 1.5e-3
      {1.8e-3, 0.120},   // unloading K2 (α − α0) = 400 × 0.3e-3
      {1.9e-3, 0.160},   // reloading along the unloading line
      {1.6e-3, 0.040},   // unloading
      {1.4e-3, 0.000},   // below α0: latched, zero force
      {2.5e-3, 0.250},   // past α_max: back on K1 α, α0 = 1.875e-3
      {2.4e-3, 0.210},   // unloading from the new maximum: 400 × (2.4 − 1.875)e-3
  };
  for (const Step& s : steps) {
    ContactForce out;
    ASSERT_TRUE(law->evaluate(0, kin(s.alpha), h.data(), true, out));
    EXPECT_NEAR(-out.f[0], s.force, 1e-12) << "alpha = " << s.alpha;
    EXPECT_EQ(out.f[1], 0.0);
  }
  EXPECT_NEAR(h[0], 1.875e-3, 1e-15);
  // Separation clears the history.
  ContactForce out;
  EXPECT_FALSE(law->evaluate(0, kin(-1e-6), h.data(), true, out));
  EXPECT_EQ(h[0], 0.0);
}

TEST(WaltonNormal, ElasticWhenRestitutionIsOne) {
  ContactParams p;
  p.k1 = 50.0;
  p.e = 1.0;
  auto law = law_of({NormalKind::Walton, TangentialKind::None, CohesionKind::None}, p);
  std::vector<double> h(1, 0.0);
  ContactForce out;
  law->evaluate(0, kin(2e-3), h.data(), true, out);
  law->evaluate(0, kin(1e-3), h.data(), true, out);
  EXPECT_DOUBLE_EQ(-out.f[0], 50.0 * 1e-3);
}

namespace {
// Walton tangential with F_N = 1 N (K1 = 1000 N/m at α = 1 mm, e = 1), K0 = 1000 N/m,
// μ = 0.5, γ = 1: K_T = K0 (1 − (T − T*)/(μF_N − T*)) on loading.
struct WaltonTangentialFixture : ::testing::Test {
  ContactParams p;
  std::unique_ptr<ContactLaw> law;
  std::vector<double> h;
  void SetUp() override {
    p.k1 = 1000.0;
    p.e = 1.0;
    p.kt = 1000.0;
    p.mu = 0.5;
    p.walton_gamma = 1.0;
    law = law_of({NormalKind::Walton, TangentialKind::Walton, CohesionKind::None}, p);
    h.assign(law->history_size(), 0.0);
  }
  // Tangential slip of i relative to j of −ds along y in one step (dt = 1): loads +ds.
  ContactForce push(double ds, double nx = 1, double ny = 0) {
    ContactKinematics k = kin(1e-3, nx, ny);
    k.vt[1] = -ds;
    if (ny != 0.0) {  // keep v_t tangential for a rotated normal
      const double d = k.vt[0] * nx + k.vt[1] * ny;
      k.vt[0] -= d * nx;
      k.vt[1] -= d * ny;
    }
    ContactForce out;
    EXPECT_TRUE(law->evaluate(0, k, h.data(), true, out));
    return out;
  }
};
}  // namespace

TEST_F(WaltonTangentialFixture, StickFollowsEq210LoadingBranch) {
  EXPECT_EQ(law->history_size(), 1 + 6);
  EXPECT_NEAR(push(1e-4).f[1], 0.100, 1e-12);  // K_T = K0
  EXPECT_NEAR(push(1e-4).f[1], 0.180, 1e-12);  // K_T = K0 (1 − 0.1/0.5) = 800
  EXPECT_NEAR(push(1e-4).f[1], 0.244, 1e-12);  // K_T = 640
}

TEST_F(WaltonTangentialFixture, SlipCapsAtMuFn) {
  const ContactForce out = push(1e-3);  // K0 Δs = 1 N > μ F_N = 0.5 N
  EXPECT_NEAR(out.f[1], 0.5, 1e-12);
  EXPECT_NEAR(push(1e-3).f[1], 0.5, 1e-12);
  // Normal part unchanged: −F_N along n.
  EXPECT_NEAR(out.f[0], -1.0, 1e-12);
}

TEST_F(WaltonTangentialFixture, ReversalSetsTStarAndUsesUnloadingBranch) {
  push(1e-4);
  push(1e-4);
  push(1e-4);  // T = 0.244
  // Reversal: T* = 0.244; K_T = K0 (1 − (T* − T)/(μF_N + T*)) = K0 at T = T*.
  EXPECT_NEAR(push(-1e-4).f[1], 0.144, 1e-12);
  // Next: K_T = 1000 (1 − 0.1/0.744) → T = 0.144 − 0.1 (1 − 0.1/0.744).
  EXPECT_NEAR(push(-1e-4).f[1], 0.144 - 0.1 * (1.0 - 0.1 / 0.744), 1e-12);
  EXPECT_NEAR(h[1 + 3], 0.244, 1e-12);  // T* in history
}

TEST_F(WaltonTangentialFixture, ContactPlaneRotationKeepsMagnitude) {
  push(2e-4);  // T = 0.2 along +y, n = +x
  const double th = 0.3;
  const double nx = std::cos(th), ny = std::sin(th);
  const ContactForce out = push(0.0, nx, ny);
  // Tangential part = f + F_N n (normal part of the force on i is −F_N n).
  const double t0 = out.f[0] + nx, t1 = out.f[1] + ny;
  EXPECT_NEAR(std::hypot(t0, t1), 0.2, 1e-12);  // Eq. 2.11 keeps |T|
  EXPECT_NEAR(t0 * nx + t1 * ny, 0.0, 1e-12);   // in the new tangent plane
  EXPECT_GT(t1, 0.0);
}

TEST_F(WaltonTangentialFixture, PerpendicularDisplacementSeesK0) {
  push(1e-4);  // T = 0.1 along +y
  ContactKinematics k = kin(1e-3);
  k.vt[2] = -1e-4;  // displacement along +z, perpendicular to the old force
  ContactForce out;
  law->evaluate(0, k, h.data(), true, out);
  EXPECT_NEAR(out.f[1], 0.1, 1e-12);
  EXPECT_NEAR(out.f[2], 0.1, 1e-12);  // K0 Δs_⊥
}

TEST(HookeHistory, MatchesLammpsFormulas) {
  ContactParams p;
  p.k1 = 100.0;
  p.e = 0.9;
  p.kt = 200.0 / 7.0;
  p.mu = 0.5;
  const double meff = 6.544984694978735e-07;  // two 1 mm spheres of 2500 kg/m³
  const double gn = hooke_gamma_from_restitution(p.k1, p.e, meff);
  EXPECT_NEAR(gn, 828.628, 0.01);  // the value in the reference inputs
  auto law = law_of({NormalKind::Hooke, TangentialKind::History, CohesionKind::None}, p, meff);
  EXPECT_EQ(law->history_size(), 3);
  std::vector<double> h(3, 0.0);
  ContactKinematics k = kin(1e-5);
  k.m_eff = meff;
  k.dt = 5e-6;
  k.vn = 0.1;
  k.vt[1] = 0.01;
  ContactForce out;
  law->evaluate(0, k, h.data(), true, out);
  const double fn = 100.0 * 1e-5 + meff * gn * 0.1;
  EXPECT_NEAR(-out.f[0], fn, 1e-15);
  const double shear = 0.01 * 5e-6;
  const double fs = -(p.kt * shear + meff * 0.5 * gn * 0.01);
  EXPECT_NEAR(out.f[1], fs, 1e-15);
  EXPECT_NEAR(h[1], shear, 1e-20);
  // Sliding: history rescaled so that kt·s + m γt v_t equals the cap (LAMMPS rule).
  k.vt[1] = 10.0;
  law->evaluate(0, k, h.data(), true, out);
  const double fn2 = 100.0 * 1e-5 + meff * gn * 0.1;
  EXPECT_NEAR(std::fabs(out.f[1]), 0.5 * fn2, 1e-14);
  EXPECT_NEAR(std::fabs(p.kt * h[1] + meff * 0.5 * gn * 10.0), 0.5 * fn2, 1e-14);
}

TEST(VanDerWaals, PairAndWallForcesFollowEq529) {
  ContactParams p;
  p.k1 = 1e-7;
  p.e = 0.95;
  p.hamaker = 1e-18;
  p.r_ss = 3e-10;
  p.alpha_min = 4e-10;
  p.alpha_cut = 1e-6;
  const double R = 3.175e-5;
  auto law = law_of({NormalKind::Walton, TangentialKind::None, CohesionKind::VanDerWaals}, p);
  EXPECT_DOUBLE_EQ(law->cohesion_range(), 1e-6);
  std::vector<double> h(1, 0.0);
  const double rss6 = std::pow(3e-10, 6);
  for (double a : {5e-10, 1e-9, 1e-8, 1e-7, 9e-7}) {
    ContactKinematics k = kin(-a);
    k.r_eff = 0.5 * R;  // equal spheres
    ContactForce out;
    ASSERT_TRUE(law->evaluate(0, k, h.data(), true, out));
    const double eq528 = 1e-18 * R / (12 * a * a) * (1 - rss6 / (60 * std::pow(a, 6)));
    EXPECT_NEAR(out.f[0], eq528, 1e-12 * eq528) << a;  // attraction: towards j (+n)
    k.wall = true;
    k.r_eff = R;
    law->evaluate(0, k, h.data(), true, out);
    const double eq521 = 1e-18 * R / (6 * a * a) * (1 - rss6 / (60 * std::pow(a, 6)));
    EXPECT_NEAR(out.f[0], eq521, 1e-12 * eq521) << a;
  }
  // Constant inside α_min, also during overlap (added to the spring).
  const double fmin = 1e-18 * R / (12 * 16e-20) * (1 - rss6 / (60 * std::pow(4e-10, 6)));
  ContactKinematics k = kin(-1e-10);
  k.r_eff = 0.5 * R;
  ContactForce out;
  law->evaluate(0, k, h.data(), true, out);
  EXPECT_NEAR(out.f[0], fmin, 1e-12 * fmin);
  k.delta = 1e-9;
  law->evaluate(0, k, h.data(), true, out);
  EXPECT_NEAR(out.f[0], fmin - 1e-7 * 1e-9, 1e-12 * fmin);
  // Zero beyond the cutoff.
  k.delta = -1.1e-6;
  EXPECT_FALSE(law->evaluate(0, k, h.data(), true, out));
}

TEST(TimeStep, Eq223) {
  const double m = 5026.0, k1 = 1e-7, e = 0.95;
  EXPECT_DOUBLE_EQ(walton_time_step(m, k1, e, 50), std::numbers::pi * e * std::sqrt(m / (2 * k1)) / 50);
  EXPECT_DOUBLE_EQ(walton_collision_time(m / 2, k1, e), std::numbers::pi * std::sqrt(m / 2 / (k1 / (e * e))));
}
