// Pins the pair collision time of seed 003 Eq. 2.3–2.5 on hand-computed cases, and the
// periodic image found through cell offsets.
#include <bit>
#include <cmath>
#include <cstdint>

#include <gtest/gtest.h>

#include "engine/core/rng.hpp"
#include "engine/ed/pair_collision_time.hpp"
#include "engine/ed/simulation.hpp"

namespace ed = grainflow::ed;

TEST(PairCollisionTime, HeadOnApproach) {
  // Centres 3 apart closing at 2: contact when the gap 3 − 1 = 2 is closed, t = 1.
  EXPECT_DOUBLE_EQ(ed::pair_collision_time(3.0, 0.0, -2.0, 0.0, 1.0), 1.0);
}

TEST(PairCollisionTime, OffsetApproach) {
  // r = (4, 0.6), v = (−1, 0): contact when (4 − t)² + 0.36 = 1 → t = 4 − 0.8 = 3.2.
  EXPECT_NEAR(ed::pair_collision_time(4.0, 0.6, -1.0, 0.0, 1.0), 3.2, 1e-14);
}

TEST(PairCollisionTime, RecedingIsNever) {
  EXPECT_EQ(ed::pair_collision_time(3.0, 0.0, 1.0, 0.0, 1.0), ed::kNever);
  // Perpendicular motion: b = r·v = 0 counts as not approaching.
  EXPECT_EQ(ed::pair_collision_time(3.0, 0.0, 0.0, 1.0, 1.0), ed::kNever);
}

TEST(PairCollisionTime, GrazingMissAndTouch) {
  // Impact parameter 1.0001 > σ: miss; 0.9999: hit at t = 5 − sqrt(1 − 0.9999²).
  EXPECT_EQ(ed::pair_collision_time(5.0, 1.0001, -1.0, 0.0, 1.0), ed::kNever);
  EXPECT_NEAR(ed::pair_collision_time(5.0, 0.9999, -1.0, 0.0, 1.0),
              5.0 - std::sqrt(1.0 - 0.9999 * 0.9999), 1e-12);
}

TEST(PairCollisionTime, FarPairIsAccurate) {
  // Cancellation-free root: r = 1e6 with closing speed 1 gives t = 1e6 − 1 to ~1 ulp.
  EXPECT_NEAR(ed::pair_collision_time(1e6, 0.0, -1.0, 0.0, 1.0), 1e6 - 1.0, 1e-9);
  // Slightly overlapping and approaching (round-off): collide now.
  EXPECT_EQ(ed::pair_collision_time(1.0 - 1e-15, 0.0, -1.0, 0.0, 1.0), 0.0);
}

TEST(PairCollisionTime, BranchlessVariantIsBitIdentical) {
  // The neighbourhood scan uses the branch-free form; it must return the same bits as the
  // reference for approaching, receding, grazing, touching, overlapping and far pairs.
  grainflow::core::Rng rng(5);
  auto bits = [](double x) { return std::bit_cast<std::uint64_t>(x); };
  int approaching = 0, hits = 0;
  for (int k = 0; k < 200000; ++k) {
    const double scale = k % 3 == 0 ? 1.0 : (k % 3 == 1 ? 1e-3 : 1e3);
    const double dx = scale * (2.0 * rng.uniform() - 1.0), dy = scale * (2.0 * rng.uniform() - 1.0);
    const double dvx = rng.normal(), dvy = rng.normal();
    const double sigma = 0.5 + rng.uniform();
    const double ref = ed::pair_collision_time(dx, dy, dvx, dvy, sigma);
    ASSERT_EQ(bits(ed::pair_collision_time_branchless(dx, dy, dvx, dvy, sigma)), bits(ref))
        << dx << " " << dy << " " << dvx << " " << dvy << " " << sigma;
    approaching += dx * dvx + dy * dvy < 0.0;
    hits += ref < ed::kNever;
  }
  // The sample covers every branch: receding, misses, hits (and contact-now at scale 1e-3).
  EXPECT_GT(approaching, 80000);
  EXPECT_GT(hits, 20000);
  EXPECT_LT(hits, approaching);
  for (double c : {3.0, 1.0 - 1e-15, 1.0, 0.5})
    EXPECT_EQ(bits(ed::pair_collision_time_branchless(c, 0.0, -1.0, 0.0, 1.0)),
              bits(ed::pair_collision_time(c, 0.0, -1.0, 0.0, 1.0)));
  EXPECT_EQ(ed::pair_collision_time_branchless(3.0, 0.0, 0.0, 1.0, 1.0), ed::kNever);
}

TEST(PairCollisionTime, PeriodicImageThroughCells) {
  // Two disks near opposite x edges of a periodic 10 × 10 box approach through the edge:
  // x1 = 0.6, x2 = 9.4 → image distance 1.2, closing at 0.4 ⇒ contact after 0.2/0.4 = 0.5.
  ed::Config cfg;
  cfg.lx = cfg.ly = 10.0;
  std::vector<ed::DiskInit> d(2);
  d[0].r = {0.6, 5.0};
  d[0].v = {-0.2, 0.0};
  d[1].r = {9.4, 5.0};
  d[1].v = {0.2, 0.0};
  for (auto cal : {ed::CalendarKind::cell_heap, ed::CalendarKind::bucket}) {
    cfg.calendar = cal;
    ed::Simulation sim(cfg, d);
    std::vector<ed::CollisionRecord> log;
    sim.set_collision_observer([&](const ed::CollisionRecord& r) { log.push_back(r); });
    sim.run_until(0.6);
    ASSERT_EQ(log.size(), 1u) << sim.calendar();
    EXPECT_NEAR(log[0].t, 0.5, 1e-12);
    // Elastic head-on, equal masses: velocities exchanged.
    EXPECT_NEAR(sim.disks()[0].vx, 0.2, 1e-14);
    EXPECT_NEAR(sim.disks()[1].vx, -0.2, 1e-14);
  }
}

TEST(PairCollisionTime, WallBounce) {
  // A disk moving at 1 towards the x = 10 wall from x = 5 (radius 0.5) bounces at t = 4.5.
  ed::Config cfg;
  cfg.lx = cfg.ly = 10.0;
  cfg.periodic_x = false;
  std::vector<ed::DiskInit> d(1);
  d[0].r = {5.0, 5.0};
  d[0].v = {1.0, 0.0};
  ed::Simulation sim(cfg, d);
  sim.run_until(4.4);
  EXPECT_EQ(sim.stats().agent_events, 0u);
  sim.run_until(4.6);
  EXPECT_EQ(sim.stats().agent_events, 1u);
  sim.synchronise();
  EXPECT_NEAR(sim.disks()[0].vx, -1.0, 1e-15);
  EXPECT_NEAR(sim.disks()[0].x, 9.5 - 0.1, 1e-12);
}
