// Moving walls and phased runs (engine/ed/elastic_walls.hpp, phase_timer.hpp): a slip
// wall exerts no shear whatever its speed (same bits as a wall at rest), flip walls
// conserve energy in their frame, thermal walls bring the gas to their temperature and,
// moving, drag it along at their speed; the re-emission is the flux distribution; phases
// fire exactly at their times and change the rule there; a thermostat switched off
// changes no velocity but keeps sampling, and switched on again resumes at once.
#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "engine/core/error.hpp"
#include "engine/core/rng.hpp"
#include "engine/ed/phase_timer.hpp"
#include "engine/ed/simulation.hpp"
#include "engine/ed/thermal_wall.hpp"
#include "engine/ed/thermostat.hpp"
#include "tests/ed/ks_statistic.hpp"

namespace ed = grainflow::ed;

namespace {

ed::Config channel(double l, double eta, double kT, std::uint64_t seed) {
  ed::Config c;
  c.lx = c.ly = l;
  c.area_fraction = eta;
  c.kT = kT;
  c.seed = seed;
  c.periodic_y = false;  // walls at y = 0 and y = Ly
  return c;
}

ed::WallConfig walls(ed::WallSurface s, double u_low, double u_high, double kT = 0.02) {
  ed::WallConfig w;
  w.surface = s;
  w.u_low = u_low;
  w.u_high = u_high;
  w.kT = kT;
  w.seed = 21;
  return w;
}

bool same_disks(const ed::Simulation& a, const ed::Simulation& b) {
  if (a.size() != b.size() || a.state().epoch() != b.state().epoch()) return false;
  for (int i = 0; i < a.size(); ++i) {
    const ed::Disk &x = a.disks()[i], &y = b.disks()[i];
    if (x.x != y.x || x.y != y.y || x.vx != y.vx || x.vy != y.vy) return false;
  }
  return true;
}

}  // namespace

TEST(EdWalls, MovingSlipWallsExertNoShear) {
  ed::Simulation rest(channel(20.0, 0.4, 0.02, 3)), moving(channel(20.0, 0.4, 0.02, 3));
  moving.walls()->configure(walls(ed::WallSurface::slip, -0.2, 0.3));
  rest.run_until(60.0);
  moving.run_until(60.0);
  EXPECT_TRUE(same_disks(rest, moving));
  EXPECT_GT(moving.walls()->hits(ed::wall_y_low), 50u);
  EXPECT_EQ(moving.walls()->momentum_given(ed::wall_y_low).x(), 0.0);
  EXPECT_EQ(moving.walls()->momentum_given(ed::wall_y_high).x(), 0.0);
}

TEST(EdWalls, FlipWallsAtRestConserveEnergyAndTakeMomentum) {
  ed::Simulation sim(channel(20.0, 0.4, 0.02, 4));
  sim.walls()->configure(walls(ed::WallSurface::flip, 0.0, 0.0));
  const double k0 = sim.kinetic_energy();
  sim.run_until(80.0);
  EXPECT_NEAR(sim.kinetic_energy(), k0, 1e-12 * k0);
  // Every flip reverses the tangential velocity: momentum goes to the walls and back.
  double moved = 0.0;
  for (auto w : {ed::wall_y_low, ed::wall_y_high}) moved += std::abs(sim.walls()->momentum_given(w).x());
  EXPECT_GT(moved, 0.1);
  EXPECT_NEAR(sim.walls()->energy_given(ed::wall_y_low) + sim.walls()->energy_given(ed::wall_y_high), 0.0, 1e-12);
}

TEST(EdWalls, ThermalWallsBringTheGasToTheirTemperature) {
  // A dilute gas (≈ 170 disks) started at 0.01 between walls at 0.03: kT → 0.03; the
  // energy the walls gave is the gas's gain (elastic collisions). The gas's energy
  // fluctuates canonically (≈ 1/√N per relaxation time of ≈ 150): averaged over ≈ 100 of
  // them, 3 % is 4 standard errors.
  ed::Simulation sim(channel(30.0, 0.15, 0.01, 5));
  sim.walls()->configure(walls(ed::WallSurface::thermal, 0.0, 0.0, 0.03));
  const double k0 = sim.kinetic_energy();
  sim.run_until(1500.0);
  sim.reset_measurements();
  sim.run_until(16500.0);
  EXPECT_NEAR(sim.observables().kT, 0.03, 0.03 * 0.03);
  const double given = sim.walls()->energy_given(ed::wall_y_low) + sim.walls()->energy_given(ed::wall_y_high);
  EXPECT_NEAR(sim.kinetic_energy() - k0, given, 1e-9 * k0);
}

TEST(EdWalls, MovingThermalWallsDragTheGasAlong) {
  // Both walls at +0.1 (in their frame the gas comes to rest): the mean velocity → 0.1.
  ed::Simulation sim(channel(16.0, 0.2, 0.02, 6));
  sim.walls()->configure(walls(ed::WallSurface::thermal, 0.1, 0.1));
  sim.run_until(3000.0);
  double vx = 0.0;
  const int samples = 40;
  for (int k = 0; k < samples; ++k) {
    sim.run_until(3000.0 + 50.0 * (k + 1));
    vx += sim.momentum().x() / sim.count();
  }
  EXPECT_NEAR(vx / samples, 0.1, 0.01);
}

TEST(EdWalls, ThermalReemissionIsTheFluxDistribution) {
  grainflow::core::Rng rng(9);
  const double kT = 0.02, m = 2.0, s2 = kT / m;
  std::vector<double> vn, vt;
  for (int k = 0; k < 20000; ++k) {
    const ed::WallFrameVelocity v = ed::thermal_reemission(rng, kT, m);
    vn.push_back(v.normal);
    vt.push_back(v.tangential);
  }
  // Flux-weighted normal speed: Rayleigh, F = 1 − exp(−v²/2s²); tangential: Gaussian.
  const double dn = grainflow::test::ks_statistic(vn, [&](double v) { return 1.0 - std::exp(-v * v / (2 * s2)); });
  const double dt = grainflow::test::ks_statistic(
      vt, [&](double v) { return 0.5 * std::erfc(-v / std::sqrt(2 * s2)); });
  EXPECT_LT(dn, grainflow::test::ks_critical_001(vn.size()));
  EXPECT_LT(dt, grainflow::test::ks_critical_001(vt.size()));
}

TEST(EdWalls, ConfigureRefusesBadValues) {
  ed::Simulation sim(channel(20.0, 0.3, 0.02, 7));
  ed::WallConfig w = walls(ed::WallSurface::thermal, 0.0, 0.0, -1.0);
  EXPECT_THROW(sim.walls()->configure(w), grainflow::Error);
  w = walls(ed::WallSurface::slip, 0.0, 0.0);
  w.restitution = 1.5;
  EXPECT_THROW(sim.walls()->configure(w), grainflow::Error);
  // Walls in x only: they cannot move.
  ed::Config c = channel(20.0, 0.3, 0.02, 7);
  c.periodic_y = true;
  c.periodic_x = false;
  ed::Simulation side(c);
  ASSERT_NE(side.walls(), nullptr);
  EXPECT_THROW(side.walls()->configure(walls(ed::WallSurface::slip, 0.1, 0.0)), grainflow::Error);
  ed::Config periodic = c;
  periodic.periodic_x = true;
  EXPECT_EQ(ed::Simulation(periodic).walls(), nullptr);
}

TEST(EdPhases, FireExactlyAtTheirTimesAndChangeTheRuleThere) {
  ed::Config c = channel(20.0, 0.5, 0.02, 8);
  c.periodic_y = true;
  c.tau_tc = 1e-4;
  ed::Simulation sim(c);
  std::vector<double> fired, e_seen;
  ed::Simulation* s = &sim;
  const std::vector<double> times = {1.5, 2.0 / 3.0 + 2.0, 7.0};
  sim.emplace_timer<ed::PhaseTimer>(
      times,
      [&, s](ed::SystemState& st, std::size_t k) {
        fired.push_back(st.now());
        e_seen.push_back(s->restitution());
        s->set_restitution(k == 1 ? 0.8 : 1.0);
      },
      sim.time());
  // Stops that do not fall on the phase times change nothing.
  for (double t : {1.0, 2.5, 2.9, 5.0}) sim.run_until(t);
  ASSERT_EQ(fired.size(), 2u);
  EXPECT_EQ(fired[0], times[0]);
  EXPECT_EQ(fired[1], times[1]);
  EXPECT_EQ(sim.restitution(), 0.8);
  const double kT_before = sim.state().kT();
  sim.run_until(6.99);
  EXPECT_LT(sim.state().kT(), 0.9 * kT_before);  // cooling between the phases
  sim.run_until(8.0);
  ASSERT_EQ(fired.size(), 3u);
  EXPECT_EQ(fired[2], 7.0);
  EXPECT_EQ(e_seen[2], 0.8);
  EXPECT_EQ(sim.restitution(), 1.0);
}

TEST(EdPhases, RefusesTimesThatDoNotIncrease) {
  auto none = [](ed::SystemState&, std::size_t) {};
  EXPECT_THROW(ed::PhaseTimer({2.0, 2.0}, none, 0.0), grainflow::Error);
  EXPECT_THROW(ed::PhaseTimer({3.0, 1.0}, none, 0.0), grainflow::Error);
  EXPECT_THROW(ed::PhaseTimer({1.0}, none, 2.0), grainflow::Error);
  EXPECT_THROW(ed::PhaseTimer({std::nan("")}, none, 0.0), grainflow::Error);
  EXPECT_NO_THROW(ed::PhaseTimer({0.0, 1.0}, none, 0.0));
}

TEST(EdPhases, AThermostatSwitchedOffChangesNothingAndResumesWhenSwitchedOn) {
  ed::Config c = channel(20.0, 0.5, 0.02, 10);
  c.periodic_y = true;
  ed::Simulation sim(c);
  ed::ThermostatConfig tc;
  tc.kT = 0.04;
  tc.tau = 1.0;
  tc.tau_v = 4.0;
  tc.sample_interval = 0.1;
  tc.grid.nx = tc.grid.ny = 4;
  tc.grid.hi = {20.0, 20.0};
  auto& th = sim.emplace_timer<ed::Thermostat>(tc, sim.state());
  sim.emplace_timer<ed::PhaseTimer>(
      std::vector<double>{0.0, 20.0},
      [&th](ed::SystemState& st, std::size_t k) { th.set_active(k == 1, st); }, sim.time());
  const double k0 = sim.kinetic_energy();
  sim.run_until(19.99);
  EXPECT_FALSE(th.active());
  EXPECT_EQ(th.events(), 0u);
  EXPECT_GT(th.samples(), 150u);                      // the local field is still averaged
  EXPECT_NEAR(sim.kinetic_energy(), k0, 1e-12 * k0);  // an elastic gas alone
  sim.run_until(30.0);
  EXPECT_TRUE(th.active());
  // N/τ events per unit time from t = 20 on: ≈ 10 N, within 5 σ of Poisson.
  const double expected = 10.0 * sim.count();
  EXPECT_NEAR(double(th.events()), expected, 5 * std::sqrt(expected));
  EXPECT_GT(sim.state().kT(), 0.025);  // heating towards 0.04
}
