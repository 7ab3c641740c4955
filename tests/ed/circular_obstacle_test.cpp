// The fixed circular obstacle (seed 003 §4.1, §5): specular slip bounce on a hand-computed
// case, momentum balance between disks and obstacle (drag), no disk ever inside it, and
// thermal re-emission that brings a dilute gas to the boundary temperature [TTKB98].
#include <cmath>

#include <gtest/gtest.h>

#include "engine/core/error.hpp"
#include "engine/ed/simulation.hpp"

namespace ed = grainflow::ed;

TEST(CircularObstacle, SlipHeadOnBounce) {
  ed::Config c;
  c.lx = c.ly = 20.0;
  std::vector<ed::DiskInit> d(1);
  d[0].r = {5.0, 10.0};
  d[0].v = {1.0, 0.0};
  ed::Simulation sim(c, d);
  ed::ObstacleConfig o;
  o.centre = {10.0, 10.0};
  o.radius = 2.0;
  auto& obs = sim.add_obstacle(o);
  sim.run_until(2.4);
  EXPECT_EQ(obs.hits(), 0u);
  sim.run_until(2.6);  // contact at x = 10 − 2.5 = 7.5, t = 2.5
  EXPECT_EQ(obs.hits(), 1u);
  EXPECT_NEAR(sim.disks()[0].vx, -1.0, 1e-15);
  EXPECT_NEAR(obs.impulse().x(), 2.0, 1e-15);
}

TEST(CircularObstacle, SlipStreamMomentumBalanceAndNoPenetration) {
  ed::Config c;
  c.lx = 40.0;
  c.ly = 30.0;
  c.area_fraction = 0.6;
  c.stream = {0.1, 0.0};
  ed::Simulation sim(c);
  ed::ObstacleConfig o;
  o.centre = {15.0, 15.0};
  o.radius = 5.0;
  auto& obs = sim.add_obstacle(o);
  const auto p0 = sim.momentum();
  const double e0 = sim.kinetic_energy();
  for (int k = 0; k < 20; ++k) {
    sim.run_until(sim.time() + 5.0);
    sim.synchronise();
    for (const auto& disk : sim.disks())
      ASSERT_GE(std::hypot(disk.x - 15.0, disk.y - 15.0), 5.5 - 1e-9);
  }
  EXPECT_GT(obs.hits(), 100u);
  EXPECT_GT(obs.impulse().x(), 0.0);  // drag along the stream
  EXPECT_NEAR((sim.momentum() + obs.impulse() - p0).norm(), 0.0, 1e-9);
  EXPECT_NEAR(sim.kinetic_energy() / e0, 1.0, 1e-9);  // specular, r = 1
  EXPECT_GE(sim.min_gap(), -1e-10);
}

TEST(CircularObstacle, ThermalReemissionSetsGasTemperature) {
  ed::Config c;
  c.lx = c.ly = 16.0;
  c.area_fraction = 0.2;
  c.kT = 0.02;
  ed::Simulation sim(c);
  ed::ObstacleConfig o;
  o.centre = {8.0, 8.0};
  o.radius = 5.0;
  o.boundary = ed::ObstacleBoundary::thermal;
  o.kT = 0.05;
  sim.add_obstacle(o);
  sim.run_until(400.0);
  sim.reset_measurements();
  sim.run_until(10400.0);
  const double kT = sim.observables().kT;
  // The obstacle does not conserve momentum, so the centre of mass is thermalised too and
  // the peculiar-velocity kT (Eq. 4.9) averages kT_b (1 − 1/N). Tolerance: noise of ~40 disks.
  const double expect = 0.05 * (1.0 - 1.0 / sim.size());
  std::printf("thermal obstacle at kT_b = 0.05: gas kT = %.4f, expected %.4f (N = %d)\n", kT, expect, sim.size());
  EXPECT_NEAR(kT, expect, expect * 0.04);
}

TEST(CircularObstacle, FlipKeepsSpeedWithElasticRestitution) {
  // Flip variant with r = 1: |v| unchanged at every hit, so the energy is conserved.
  ed::Config c;
  c.lx = c.ly = 20.0;
  c.area_fraction = 0.3;
  ed::Simulation sim(c);
  ed::ObstacleConfig o;
  o.centre = {10.0, 10.0};
  o.radius = 3.0;
  o.boundary = ed::ObstacleBoundary::flip;
  auto& obs = sim.add_obstacle(o);
  const double e0 = sim.kinetic_energy();
  sim.run_until(300.0);
  EXPECT_GT(obs.hits(), 50u);
  EXPECT_NEAR(sim.kinetic_energy() / e0, 1.0, 1e-9);
}

TEST(CircularObstacle, MustLieInsideTheBox) {
  ed::Config c;
  c.lx = c.ly = 20.0;
  c.area_fraction = 0.3;
  ed::Simulation sim(c);
  ed::ObstacleConfig o;
  o.centre = {2.0, 10.0};
  o.radius = 3.0;
  EXPECT_THROW(sim.add_obstacle(o), grainflow::Error);
}

TEST(CircularObstacle, SurfaceSwitchedAtRunTimeActsFromThen) {
  // Phased runs (seed 003 ch. 5: thermal no-slip first, then the flip): slip with r = 1
  // conserves the energy, thermal re-emission at kT_b = 0.05 then heats the gas from 0.02
  // towards kT_b, and the elastic flip conserves it again.
  ed::Config c;
  c.lx = c.ly = 16.0;
  c.area_fraction = 0.2;
  c.kT = 0.02;
  ed::Simulation sim(c);
  ed::ObstacleConfig o;
  o.centre = {8.0, 8.0};
  o.radius = 5.0;
  o.kT = 0.05;
  auto& obs = sim.add_obstacle(o);
  const double e0 = sim.kinetic_energy();
  sim.run_until(200.0);
  EXPECT_GT(obs.hits(), 50u);
  EXPECT_NEAR(sim.kinetic_energy() / e0, 1.0, 1e-9);
  obs.set_boundary(ed::ObstacleBoundary::thermal);
  sim.run_until(3000.0);
  const double e1 = sim.kinetic_energy();
  EXPECT_GT(e1 / e0, 0.05 / 0.02 * 0.8) << "the gas did not warm towards the thermal surface's kT";
  const auto hits = obs.hits();
  obs.set_boundary(ed::ObstacleBoundary::flip);
  sim.run_until(3200.0);
  EXPECT_GT(obs.hits(), hits + 50);
  EXPECT_NEAR(sim.kinetic_energy() / e1, 1.0, 1e-9);
}
