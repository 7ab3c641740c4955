// The sampler event source (seed 003 §4.1) in an equilibrium periodic box with a stream:
// every disk is binned at every sample, and the averaged fields recover n, U and kT.
#include <cmath>

#include <gtest/gtest.h>

#include "engine/core/error.hpp"
#include "engine/ed/field_sampler.hpp"
#include "engine/ed/simulation.hpp"

namespace ed = grainflow::ed;

TEST(FieldSampler, EquilibriumBoxFields) {
  ed::Config c;
  c.lx = c.ly = 30.0;
  c.area_fraction = 0.5;
  c.kT = 0.02;
  c.stream = {0.1, 0.0};
  ed::Simulation sim(c);
  sim.run_until(20.0);
  ed::SamplerConfig sc;
  sc.grid.nx = 6;
  sc.grid.ny = 5;
  sc.grid.lo = {0.0, 0.0};
  sc.grid.hi = {c.lx, c.ly};
  sc.interval = 0.5;
  sc.exposure = 50.0;
  auto& sampler = sim.emplace_timer<ed::FieldSampler>(sc, sim.time());
  sim.run_until(120.0);
  ASSERT_EQ(sampler.frames().size(), 2u);
  const auto& f = sampler.frames()[1];
  EXPECT_EQ(f.samples, 100);
  EXPECT_NEAR(f.t_begin, 70.0, 1e-9);
  EXPECT_NEAR(f.t_end, 120.0, 1e-9);
  EXPECT_EQ(sim.stats().timer_events, 200u);
  // Every disk lands in some bin at every sample: Σ density × bin area = N exactly.
  const double bin_area = sc.grid.dx() * sc.grid.dy();
  double total = 0.0, vx = 0.0, vy = 0.0, kT = 0.0;
  for (std::size_t b = 0; b < f.fields.density.values.size(); ++b) {
    total += f.fields.density.values[b] * bin_area;
    vx += f.fields.mean_velocity->values[b].x();
    vy += f.fields.mean_velocity->values[b].y();
    kT += f.fields.temperature->values[b];
  }
  const double nb = static_cast<double>(sc.grid.size());
  EXPECT_NEAR(total, sim.size(), 1e-9 * sim.size());
  // Statistical tolerances: ~19 disks per bin × 100 correlated samples.
  EXPECT_NEAR(vx / nb, 0.1, 0.01);
  EXPECT_NEAR(vy / nb, 0.0, 0.01);
  EXPECT_NEAR(kT / nb, 0.02, 0.002);
  // Elastic: the total kT stays the initial one.
  EXPECT_NEAR(sim.state().kT(), 0.02, 1e-10);
}

TEST(FieldSampler, RejectsBadTimes) {
  ed::SamplerConfig sc;
  sc.interval = 0.0;
  EXPECT_THROW(ed::FieldSampler(sc, 0.0), grainflow::Error);
  sc.interval = 2.0;
  sc.exposure = 1.0;
  EXPECT_THROW(ed::FieldSampler(sc, 0.0), grainflow::Error);
}
