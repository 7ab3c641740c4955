// Pins the pair collision time of seed 003 Eq. 2.3–2.5 on hand-computed cases, the
// periodic image found through cell offsets, and the four-lane scan against the scalar one.
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "engine/core/rng.hpp"
#include "engine/ed/pair_collision_time.hpp"
#include "engine/ed/scan_kernel.hpp"
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

#if defined(GRAINFLOW_ED_AVX2)
TEST(ScanKernel, FourLanesGiveTheScalarScansBits) {
  // The AVX2 scan (four candidates a step) against pair_collision_time_branchless taken
  // candidate by candidate with strict <: the same earliest time, bit for bit, and the
  // same partner, over random neighbourhoods with and without image shifts and mixed radii,
  // from no event yet and from an event already held (the lanes' skip test).
  if (!ed::scan_uses_avx2()) GTEST_SKIP() << "this CPU has no AVX2: the four-lane scan is never used";
  grainflow::core::Rng rng(11);
  const int nd = 64;
  ed::HugeVector<ed::Disk> disk(nd);
  std::vector<ed::DiskBody> body(nd);
  int improved = 0, skipped = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    for (int j = 0; j < nd; ++j) {
      disk[j] = ed::Disk{rng.uniform() * 4.0, rng.uniform() * 4.0, rng.uniform() - 0.5, rng.uniform() - 0.5};
      body[j].r = 0.3 + 0.2 * rng.uniform();
    }
    const bool mixed = trial % 3 == 0, shifted = trial % 2 == 0;
    const double since = 0.3 * rng.uniform(), ur = 0.5;
    const int i = static_cast<int>(rng.uniform() * nd);
    const ed::Disk& d = disk[i];
    const ed::Disk di{d.x + d.vx * since, d.y + d.vy * since, d.vx, d.vy};
    const double ri = mixed ? body[i].r : ur;
    double shx[9] = {}, shy[9] = {};
    if (shifted)
      for (int k = 0; k < 9; ++k) {
        shx[k] = (k % 3 - 1) * 4.0;
        shy[k] = (k / 3 - 1) * 4.0;
      }
    const int n = 1 + static_cast<int>(rng.uniform() * 12);
    std::vector<ed::ScanCandidate> cand(n + ed::kScanPad, ed::ScanCandidate{i, 0});
    for (int q = 0; q < n; ++q) {
      int j = static_cast<int>(rng.uniform() * nd);
      if (j == i) j = (j + 1) % nd;
      cand[q] = ed::ScanCandidate{j, static_cast<int>(rng.uniform() * 9)};
    }
    // From no event, or from one held at a time some of the candidates beat.
    const double held = trial % 4 == 1 ? 0.5 * rng.uniform() : ed::kNever;
    double ref = held;
    int ref_who = -1;
    for (int q = 0; q < n; ++q) {
      const ed::Disk& dj = disk[cand[q].j];
      const int k = cand[q].k;
      const double t = ed::pair_collision_time_branchless(
          di.x - (dj.x + dj.vx * since + shx[k]), di.y - (dj.y + dj.vy * since + shy[k]), di.vx - dj.vx,
          di.vy - dj.vy, ri + (mixed ? body[cand[q].j].r : ur));
      if (t < ref) {
        ref = t;
        ref_who = cand[q].j;
      }
    }
    double best = held;
    int who = -1;
    ed::earliest_pair_avx2(ed::ScanQuery{disk.data(), body.data(), shx, shy, di, ri, ur, since, mixed, shifted},
                           cand.data(), n, best, who);
    ASSERT_EQ(std::bit_cast<std::uint64_t>(best), std::bit_cast<std::uint64_t>(ref)) << "trial " << trial;
    ASSERT_EQ(who, ref_who) << "trial " << trial;
    improved += ref < held;
    skipped += ref == held && held < ed::kNever;
  }
  // Both outcomes occur often enough for the comparison to mean something.
  EXPECT_GT(improved, 5000);
  EXPECT_GT(skipped, 500);
}

TEST(ScanKernel, TwoLaneAndFourLaneRunsAreTheSame) {
  // A whole run with either scan: the same collisions, pair by pair, at the same times.
  if (!ed::scan_uses_avx2()) GTEST_SKIP() << "this CPU has no AVX2: only the two-lane scan runs";
  std::vector<ed::CollisionRecord> seq[2];
  for (int pass = 0; pass < 2; ++pass) {
    ed::scan_uses_avx2() = pass == 0;
    ed::Config c;
    c.lx = 40.0;
    c.ly = 30.0;
    c.area_fraction = 0.6;
    c.periodic_y = false;  // walls on one axis, images on the other
    ed::Simulation sim(c);
    sim.set_collision_observer([&](const ed::CollisionRecord& r) { seq[pass].push_back(r); });
    while (seq[pass].size() < 100000) sim.advance(10000);
    seq[pass].resize(100000);
  }
  ed::scan_uses_avx2() = true;
  for (std::size_t k = 0; k < seq[0].size(); ++k) {
    ASSERT_EQ(seq[0][k].i, seq[1][k].i) << k;
    ASSERT_EQ(seq[0][k].j, seq[1][k].j) << k;
    ASSERT_EQ(std::bit_cast<std::uint64_t>(seq[0][k].t), std::bit_cast<std::uint64_t>(seq[1][k].t)) << k;
  }
}
#endif
