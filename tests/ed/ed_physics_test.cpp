// Physics validation of the ED engine: initial state, energy/momentum conservation in an
// elastic periodic box, the mean free time of seed 003 (0.43 at η = 0.65, kT = 0.02), and
// the collision-virial pressure against Henderson's hard-disk equation of state.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>

#include "engine/core/error.hpp"
#include "engine/ed/simulation.hpp"

namespace ed = grainflow::ed;

TEST(EdInitialState, LatticeAreaFractionTemperatureAndStream) {
  ed::Config c;
  c.lx = 50.0;
  c.ly = 40.0;
  c.area_fraction = 0.70;
  c.kT = 0.02;
  c.stream = {0.1, -0.05};
  ed::Simulation sim(c);
  EXPECT_NEAR(sim.area_fraction(), 0.70, 1e-3);
  EXPECT_GE(sim.min_gap(), 0.0);
  const auto p = sim.momentum();
  EXPECT_NEAR(p.x() / sim.size(), 0.1, 1e-12);
  EXPECT_NEAR(p.y() / sim.size(), -0.05, 1e-12);
  EXPECT_NEAR(sim.state().kT(), 0.02, 1e-12);
  // Same seed ⇒ same numbers.
  ed::Simulation again(c);
  EXPECT_EQ(sim.disks()[17].vx, again.disks()[17].vx);
  EXPECT_EQ(sim.disks()[17].x, again.disks()[17].x);
}

TEST(EdInitialState, ImpossibleConfigurationsAreErrors) {
  ed::Config c;
  c.lx = c.ly = 10.0;
  c.area_fraction = 0.95;
  EXPECT_THROW(ed::Simulation{c}, grainflow::Error);
  c.area_fraction = 0.5;
  c.min_cell_size = 0.9;  // smaller than a diameter
  EXPECT_THROW(ed::Simulation{c}, grainflow::Error);
  c.min_cell_size = 1.2;
  std::vector<ed::DiskInit> d(2);
  d[0].r = {2.0, 2.0};
  d[1].r = {2.5, 2.0};  // overlapping
  EXPECT_THROW(ed::Simulation(c, d), grainflow::Error);
  EXPECT_THROW(ed::calendar_from_name("splay"), grainflow::Error);
}

TEST(EdConservation, ElasticPeriodicBoxMillionCollisions) {
  for (auto cal : {ed::CalendarKind::bucket, ed::CalendarKind::cell_heap}) {
    ed::Config c;
    c.lx = c.ly = 40.0;
    c.area_fraction = 0.65;
    c.kT = 0.02;
    c.stream = {0.03, 0.0};
    c.calendar = cal;
    ed::Simulation sim(c);
    const double e0 = sim.kinetic_energy();
    const auto p0 = sim.momentum();
    const auto t0 = std::chrono::steady_clock::now();
    while (sim.stats().collisions < 1000000) sim.advance(100000);
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("[ %s ] %llu collisions in %.2f s; relative energy drift %.3g\n", sim.calendar(),
                static_cast<unsigned long long>(sim.stats().collisions), secs,
                sim.kinetic_energy() / e0 - 1.0);
    EXPECT_NEAR(sim.kinetic_energy() / e0, 1.0, 1e-9);
    EXPECT_NEAR((sim.momentum() - p0).norm(), 0.0, 1e-9 * sim.size());
    EXPECT_NEAR(sim.state().kinetic() / sim.kinetic_energy(), 1.0, 1e-9);  // incremental books
    EXPECT_GE(sim.min_gap(), -1e-10);
  }
}

namespace {
// Equilibrated elastic periodic box; returns observables over [t_eq, t_eq + t_meas].
ed::Observables equilibrium(double eta, double kT, double l, double t_eq, double t_meas, std::uint64_t seed) {
  ed::Config c;
  c.lx = c.ly = l;
  c.area_fraction = eta;
  c.kT = kT;
  c.seed = seed;
  ed::Simulation sim(c);
  sim.run_until(t_eq);
  sim.reset_measurements();
  sim.run_until(t_eq + t_meas);
  return sim.observables();
}
// Henderson 1975 (Mol. Phys. 30, 971): Z = (1 + η²/8)/(1 − η)² for the hard-disk fluid.
double henderson_z(double eta) { return (1.0 + eta * eta / 8.0) / ((1.0 - eta) * (1.0 - eta)); }
}  // namespace

TEST(EdEquilibrium, MeanFreeTimeMatchesSeed) {
  // Mean free time τ = mean time between collisions of one disk = t N / (2 C) (each
  // collision involves two disks). Seed 003 §4.1 quotes 0.43 at η = 0.65, kT = 0.02.
  // Enskog with Henderson's contact value gives τ_E = 1/(2 n σ g(σ) sqrt(π kT/m)) ≈ 0.41.
  const auto o = equilibrium(0.65, 0.02, 50.0, 100.0, 200.0, 11);
  std::printf("eta 0.65 kT 0.02: mean free time %.4f (seed 0.43), kT %.5f, collisions %llu\n",
              o.mean_free_time, o.kT, static_cast<unsigned long long>(o.collisions));
  EXPECT_NEAR(o.kT, 0.02, 1e-9);
  EXPECT_NEAR(o.mean_free_time, 0.43, 0.43 * 0.05);
}

TEST(EdEquilibrium, PressureMatchesHendersonEquationOfState) {
  // Z = P A/(N kT) from the collision virial vs Henderson 1975. Tolerances: Henderson's
  // fit itself deviates from simulation data by < 0.5 % at η ≤ 0.5 and by a few % near
  // the freezing density (≈ 0.70), hence 1.5 % / 1.5 % / 5 %.
  struct Case { double eta, tol; } cases[] = {{0.30, 0.015}, {0.50, 0.015}, {0.65, 0.05}};
  for (const auto& cs : cases) {
    const auto o = equilibrium(cs.eta, 1.0, 40.0, 40.0, 120.0, 5);
    const double z = henderson_z(cs.eta);
    std::printf("eta %.2f: Z = %.4f, Henderson %.4f, deviation %+.2f %%\n", cs.eta, o.compressibility, z,
                100.0 * (o.compressibility / z - 1.0));
    EXPECT_NEAR(o.compressibility / z, 1.0, cs.tol) << "eta " << cs.eta;
  }
}

TEST(EdConservation, PerfectlyRoughElasticBoxConservesTotalEnergy) {
  // e = 1, e_t = 1, μ = ∞ (never sliding): translational + rotational energy conserved
  // while energy flows between the two (ω starts Maxwellian, seed 003 §3.4).
  ed::Config c;
  c.lx = c.ly = 30.0;
  c.area_fraction = 0.5;
  c.e = 1.0;
  c.e_t = 1.0;
  c.mu = INFINITY;
  ed::Simulation sim(c);
  const double e0 = sim.kinetic_energy();
  const double rot0 = sim.state().rotational();
  EXPECT_GT(rot0, 0.0);
  sim.advance(200000);
  EXPECT_NEAR(sim.kinetic_energy() / e0, 1.0, 1e-10);
  EXPECT_NE(sim.state().rotational(), rot0);
  EXPECT_EQ(sim.stats().sliding, 0u);
  sim.synchronise();
  ASSERT_EQ(sim.state().epoch(), sim.time());  // every record holds its position now
  EXPECT_GE(sim.min_gap(), -1e-10);
}

TEST(EdConservation, InelasticRoughBoxCoolsAndKeepsBooks) {
  // e < 1 with Coulomb friction: energy only decreases, momentum stays, both sliding and
  // sticking contacts occur, and the incremental energy books follow the exact sums.
  ed::Config c;
  c.lx = c.ly = 30.0;
  c.area_fraction = 0.4;
  c.e = 0.9;
  c.e_t = 0.4;
  c.mu = 0.2;
  ed::Simulation sim(c);
  const auto p0 = sim.momentum();
  double e_prev = sim.kinetic_energy();
  for (int k = 0; k < 10; ++k) {
    sim.advance(5000);
    const double e = sim.kinetic_energy();
    EXPECT_LT(e, e_prev);
    e_prev = e;
  }
  EXPECT_NEAR((sim.momentum() - p0).norm(), 0.0, 1e-12);
  EXPECT_GT(sim.stats().sliding, 0u);
  EXPECT_LT(sim.stats().sliding, sim.stats().collisions);
  EXPECT_NEAR((sim.state().kinetic() + sim.state().rotational()) / sim.kinetic_energy(), 1.0, 1e-9);
}

TEST(EdPressureTensor, TwoDiskCollisionGivesTheExactVirialTensor) {
  // Disks at (5, 5) and (7, 7), velocities ±(1, 1), σ = m = 1, elastic and smooth: they
  // meet head on along the diagonal at t = (2√2 − 1)/(2√2) and swap velocities. At contact
  // r_12 = −(1, 1)/√2, Δp_1 = −2 (1, 1): every component of r_a Δp_b is √2. Σ m v_a v_b is 2
  // in every component before and after (total momentum 0). Over [0, t]:
  // P_ab = (2 t + √2) / (t A) for ab = xx, xy, yy.
  ed::Config c;
  c.lx = c.ly = 20.0;
  std::vector<ed::DiskInit> d(2);
  d[0].r = {5.0, 5.0};
  d[0].v = {1.0, 1.0};
  d[1].r = {7.0, 7.0};
  d[1].v = {-1.0, -1.0};
  ed::Simulation sim(c, d);
  const double t = 2.0, area = c.lx * c.ly;
  sim.run_until(t);
  ASSERT_EQ(sim.stats().collisions, 1u);
  const ed::Observables o = sim.observables();
  const double expected = (2.0 * t + std::sqrt(2.0)) / (t * area);
  EXPECT_NEAR(o.pressure_xx, expected, 1e-14);
  EXPECT_NEAR(o.pressure_xy, expected, 1e-14);
  EXPECT_NEAR(o.pressure_yy, expected, 1e-14);
  EXPECT_NEAR(0.5 * (o.pressure_xx + o.pressure_yy), o.pressure, 1e-14);
}

TEST(EdPressureTensor, EquilibriumBoxIsIsotropicAndHalfTheTraceIsThePressure) {
  // Elastic periodic box, η = 0.5: P_xx ≈ P_yy ≈ P, P_xy ≈ 0 within noise, and
  // (P_xx + P_yy)/2 = pressure to round-off (the same window, disks and area).
  const auto o = equilibrium(0.50, 1.0, 40.0, 40.0, 120.0, 5);
  std::printf("eta 0.50: P %.5f, P_xx %.5f, P_yy %.5f, P_xy %+.5f\n", o.pressure, o.pressure_xx, o.pressure_yy,
              o.pressure_xy);
  EXPECT_NEAR(0.5 * (o.pressure_xx + o.pressure_yy) / o.pressure, 1.0, 1e-12);
  EXPECT_NEAR(o.pressure_xx / o.pressure, 1.0, 0.02);
  EXPECT_NEAR(o.pressure_yy / o.pressure, 1.0, 0.02);
  EXPECT_LT(std::abs(o.pressure_xy) / o.pressure, 0.01);
}
