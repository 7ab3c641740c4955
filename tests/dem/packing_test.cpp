// Packing of a settled DEM bed (seed 000 §2.1, §4.1): contact numbers of a stacked column,
// and the bulk coordination number Z of a bed poured from random placement with radius
// growth (the `system.initial.kind = "random"` start) against one dropped from a lattice.
#include <gtest/gtest.h>

#include <cstdio>

#include "engine/dem/packing.hpp"
#include "engine/dem/simulation.hpp"

using namespace grainflow;
using namespace grainflow::dem;

namespace {

constexpr double kD = 1e-3;  // diameter [m]

// Walton contacts with friction, SI units, as scenes/dem_freefall_box.toml (K1 = 100 N/m,
// e = 0.9, μ = 0.5) but 20 steps per collision, which the settled bed does not notice.
Config bed_config(const Vec3& box) {
  Config c;
  c.box.lo = Vec3::Zero();
  c.box.hi = box;
  c.model = {NormalKind::Walton, TangentialKind::Walton, CohesionKind::None};
  GroupConfig g;
  g.radius = 0.5 * kD;
  g.density = 2500.0;
  g.contact.k1 = 100.0;
  g.contact.kt = 80.0;
  g.contact.e = 0.9;
  g.contact.mu = 0.5;
  c.groups = {g};
  c.steps_per_collision = 20;
  return c;
}

void add_particles(Config& c, const std::vector<Vec3>& sites) {
  for (const Vec3& x : sites) {
    ParticleInit p;
    p.x = x;
    c.particles.push_back(p);
  }
}

// Runs until the bed is at rest: kinetic energy below 1e-4 of the potential energy the
// bed has above its floor (checked every 0.05 s, at most `t_max`).
double settle(Simulation& s, double t_max) {
  const auto steps = std::uint64_t(0.05 / s.dt());
  double floor_pe = 0;
  for (std::size_t i = 0; i < s.size(); ++i) floor_pe += s.mass(i) * 9.81 * s.radius(i);
  while (s.time() < t_max) {
    s.step(steps);
    const Stats st = s.stats();
    if (st.kinetic < 1e-4 * (st.potential_gravity - floor_pe)) break;
  }
  return s.time();
}

}  // namespace

TEST(DemPacking, ContactNumbersOfAStackedColumnAndALoneSphere) {
  // A column of three spheres resting on the floor, and one sphere alone: the middle one
  // touches two, the ends one each (the floor is a wall, not counted), the lone one none.
  Config c = bed_config(Vec3(6 * kD, 6 * kD, 8 * kD));
  add_particles(c, {Vec3(2 * kD, 2 * kD, 0.6 * kD), Vec3(2 * kD, 2 * kD, 1.7 * kD), Vec3(2 * kD, 2 * kD, 2.8 * kD),
                    Vec3(4.5 * kD, 4.5 * kD, 0.6 * kD)});
  Simulation s(c);
  EXPECT_EQ(contact_numbers(s), (std::vector<int>{0, 0, 0, 0}));  // released 0.1 d apart
  settle(s, 1.0);
  EXPECT_EQ(contact_numbers(s), (std::vector<int>{1, 2, 1, 0}));
  EXPECT_EQ(s.stats().contacts, 2u);
}

TEST(DemPacking, BedFromRandomPlacementWithGrowthHasFrictionalCoordination) {
  // 3,000 spheres in a 16 d × 16 d base, placed at random in the lowest 24 d of the box at
  // half their radius, grown to full size over 1,000 steps, and settled under gravity.
  // Random packings of frictional spheres have Z ≈ 4–6 (4 at infinite friction, 6 without
  // friction); bulk = at least 2 d from the walls and below the free surface.
  const Vec3 box(16 * kD, 16 * kD, 32 * kD);
  Config c = bed_config(box);
  c.growth_start = 0.5;
  c.growth_steps = 1000;
  add_particles(c, random_positions(Vec3::Zero(), Vec3(box.x(), box.y(), 24 * kD), 0.25 * kD, 3000, 1));
  Simulation s(c);
  const double t = settle(s, 1.5);
  const BulkCoordination z = bulk_coordination(s, 2 * kD);
  std::printf("random start: settled at t = %.3g s, bulk Z = %.3f over %zu spheres (z %.3g–%.3g m)\n", t, z.mean,
              z.particles, z.z_lo, z.z_hi);
  EXPECT_LT(t, 1.5);
  EXPECT_GT(z.particles, 500u);
  EXPECT_GT(z.mean, 4.0);
  EXPECT_LT(z.mean, 6.0);
}

TEST(DemPacking, BedDroppedFromALatticeStacksColumnsAndFailsTheBand) {
  // The same spheres on a simple cubic lattice (spacing 1.1 d) fall in step and stack in
  // columns: each touches the one above and below, Z ≈ 2, far below a granular bed's.
  const Vec3 box(16 * kD, 16 * kD, 32 * kD);
  Config c = bed_config(box);
  add_particles(c, simple_cubic_lattice(Vec3::Zero(), 1.1 * kD, 14, 14, 15));
  Simulation s(c);
  settle(s, 1.5);
  const BulkCoordination z = bulk_coordination(s, 2 * kD);
  std::printf("lattice start: bulk Z = %.3f over %zu spheres\n", z.mean, z.particles);
  EXPECT_GT(z.particles, 300u);
  EXPECT_LT(z.mean, 3.0);
}
