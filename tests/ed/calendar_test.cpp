// Cells and both calendars against a brute-force O(N²) reference (seed 003 §2.1–2.4):
// collision by collision the engine must perform the true next event of the current
// state (same pair, same time to 1e-9); both calendars must give the same sequence; no
// pair may ever overlap.
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "engine/core/rng.hpp"
#include "engine/ed/pair_collision_time.hpp"
#include "engine/ed/simulation.hpp"
#include "tests/ed/plane_probe.hpp"

namespace ed = grainflow::ed;

namespace {

// Next event of the synchronised system by brute force over all pairs and all 9 images;
// j = −1 marks a wall event of disk i.
struct RefEvent {
  double dt;
  int i, j;
};
RefEvent brute_force_next(const ed::Simulation& sim) {
  const auto& d = sim.disks();
  const auto& rb = sim.bodies();
  const auto& c = sim.config();
  RefEvent best{ed::kNever, -1, -1};
  const int n = sim.size();
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j)
      for (int kx = -1; kx <= 1; ++kx)
        for (int ky = -1; ky <= 1; ++ky) {
          if ((kx && !c.periodic_x) || (ky && !c.periodic_y)) continue;
          const double t = ed::pair_collision_time(d[i].x - d[j].x - kx * c.lx, d[i].y - d[j].y - ky * c.ly,
                                                   d[i].vx - d[j].vx, d[i].vy - d[j].vy, rb[i].r + rb[j].r);
          if (t < best.dt) best = {t, i, j};
        }
    auto wall = [&](double p, double v, double l) {
      if (v > 0) return (l - rb[i].r - p) / v;
      if (v < 0) return (rb[i].r - p) / v;
      return ed::kNever;
    };
    if (!c.periodic_x && wall(d[i].x, d[i].vx, c.lx) < best.dt) best = {wall(d[i].x, d[i].vx, c.lx), i, -1};
    if (!c.periodic_y && wall(d[i].y, d[i].vy, c.ly) < best.dt) best = {wall(d[i].y, d[i].vy, c.ly), i, -1};
  }
  return best;
}

void check_against_brute_force(ed::Simulation& sim, int n_events) {
  ed::CollisionRecord last{-1, -1, 0.0};
  sim.set_collision_observer([&](const ed::CollisionRecord& r) { last = r; });
  for (int k = 0; k < n_events; ++k) {
    sim.synchronise();
    const RefEvent ref = brute_force_next(sim);
    ASSERT_LT(ref.dt, ed::kNever);
    const double t_ref = sim.time() + ref.dt;
    const auto before = sim.stats().collisions + sim.stats().agent_events;
    const auto walls_before = sim.stats().agent_events;
    while (sim.stats().collisions + sim.stats().agent_events == before) ASSERT_EQ(sim.advance(1), 1u);
    if (ref.j < 0) {
      ASSERT_EQ(sim.stats().agent_events, walls_before + 1) << "event " << k << ": expected a wall hit of " << ref.i;
      ASSERT_NEAR(sim.time(), t_ref, 1e-9) << "event " << k;
    } else {
      ASSERT_EQ(sim.stats().agent_events, walls_before) << "event " << k << ": expected pair " << ref.i << "," << ref.j;
      ASSERT_EQ(std::min(last.i, last.j), ref.i) << "event " << k;
      ASSERT_EQ(std::max(last.i, last.j), ref.j) << "event " << k;
      ASSERT_NEAR(last.t, t_ref, 1e-9) << "event " << k;
    }
  }
}

void check_against_brute_force(ed::Config cfg, int n_events) {
  ed::Simulation sim(cfg);
  check_against_brute_force(sim, n_events);
}

ed::Config small_box(ed::CalendarKind cal, bool px, bool py, double eta, double e = 1.0) {
  ed::Config c;
  c.lx = 9.0;
  c.ly = 7.5;
  c.area_fraction = eta;
  c.kT = 1.0;
  c.seed = 7;
  c.periodic_x = px;
  c.periodic_y = py;
  c.calendar = cal;
  c.e = e;
  return c;
}

}  // namespace

TEST(CalendarVsBruteForce, PeriodicCellHeap) {
  check_against_brute_force(small_box(ed::CalendarKind::cell_heap, true, true, 0.6), 3000);
}
TEST(CalendarVsBruteForce, PeriodicBucket) {
  check_against_brute_force(small_box(ed::CalendarKind::bucket, true, true, 0.6), 3000);
}
TEST(CalendarVsBruteForce, WallsAndPeriodicBucket) {
  check_against_brute_force(small_box(ed::CalendarKind::bucket, false, true, 0.45), 3000);
}
TEST(CalendarVsBruteForce, WallsCellHeapInelasticRough) {
  auto c = small_box(ed::CalendarKind::cell_heap, false, false, 0.45, 0.9);
  c.mu = 0.3;
  c.e_t = 0.4;
  check_against_brute_force(c, 2000);
}

TEST(CalendarVsBruteForce, PolydisperseBothCalendars) {
  // Diameters 0.7–1.0: cells hold more disks and σ_ij varies pair by pair, which the
  // vectorised neighbourhood scan (two candidates per step) must carry lane by lane.
  for (auto cal : {ed::CalendarKind::cell_heap, ed::CalendarKind::bucket}) {
    ed::Config c = small_box(cal, true, true, 0.6);
    grainflow::core::Rng rng(11);
    auto disks = ed::triangular_lattice(42, 1.0, c.lx, c.ly, true, true, rng);
    for (auto& d : disks) d.radius = 0.35 + 0.15 * rng.uniform();
    ed::maxwell_velocities(disks, 1.0, {0.0, 0.0}, false, 0.5, rng);
    ed::Simulation sim(c, disks);
    check_against_brute_force(sim, 3000);
  }
}

TEST(CalendarVsBruteForce, CalendarsGiveTheSameSequence) {
  // Without any synchronisation the two calendars must perform the identical sequence.
  std::vector<ed::CollisionRecord> seq[2];
  int k = 0;
  for (auto cal : {ed::CalendarKind::cell_heap, ed::CalendarKind::bucket}) {
    ed::Config c;
    c.lx = c.ly = 20.0;
    c.area_fraction = 0.65;
    c.seed = 3;
    c.calendar = cal;
    ed::Simulation sim(c);
    auto& s = seq[k++];
    sim.set_collision_observer([&](const ed::CollisionRecord& r) { s.push_back(r); });
    while (s.size() < 50000) sim.advance(1000);
    s.resize(50000);
  }
  for (std::size_t n = 0; n < seq[0].size(); ++n) {
    ASSERT_EQ(seq[0][n].i, seq[1][n].i) << n;
    ASSERT_EQ(seq[0][n].j, seq[1][n].j) << n;
    ASSERT_NEAR(seq[0][n].t, seq[1][n].t, 1e-9) << n;
  }
}

TEST(CalendarVsBruteForce, NoOverlapAtHighDensity) {
  for (auto cal : {ed::CalendarKind::cell_heap, ed::CalendarKind::bucket}) {
    ed::Config c;
    c.lx = 30.0;
    c.ly = 24.0;
    c.area_fraction = 0.72;
    c.periodic_y = false;
    c.calendar = cal;
    ed::Simulation sim(c);
    EXPECT_NEAR(sim.area_fraction(), 0.72, 0.002);
    for (int k = 0; k < 40; ++k) {
      sim.advance(10000);
      EXPECT_GE(sim.min_gap(), -1e-10) << "after " << sim.stats().events << " events";
    }
    EXPECT_GT(sim.stats().collisions, 100000u);
  }
}

// An event record keeps the time of its earlier event only (NextEvent): a pair or agent
// event that comes after a cell crossing is found again when the crossing is processed.
TEST(HeldEvents, PairHeldAcrossBothPartiesCrossingsHappensOnTime) {
  // One-diameter cells of width 1 (a 20 × 20 box). A at x = 4.9 (cell 4) moves at +1, B at
  // x = 5.99 (cell 5) at +0.5: B crosses x = 6 at t = 0.02, A crosses x = 5 at t = 0.1,
  // and they meet, 1 apart, at t = 0.18 (A at 5.08, B at 6.08), swapping velocities.
  for (auto cal : {ed::CalendarKind::cell_heap, ed::CalendarKind::bucket}) {
    ed::Config c;
    c.lx = c.ly = 20.0;
    c.calendar = cal;
    std::vector<ed::DiskInit> d(2);
    d[0].r = {4.9, 5.0};
    d[0].v = {1.0, 0.0};
    d[1].r = {5.99, 5.0};
    d[1].v = {0.5, 0.0};
    ed::Simulation sim(c, d);
    ASSERT_EQ(sim.state().grid.width(), 1.0);
    std::vector<ed::CollisionRecord> seen;
    sim.set_collision_observer([&](const ed::CollisionRecord& r) { seen.push_back(r); });
    sim.run_until(0.5);
    ASSERT_EQ(seen.size(), 1u);
    EXPECT_NEAR(seen[0].t, 0.18, 1e-12);
    EXPECT_GE(sim.stats().cell_crossings, 2u);
    sim.synchronise();
    EXPECT_NEAR(sim.disks()[0].vx, 0.5, 1e-12);
    EXPECT_NEAR(sim.disks()[1].vx, 1.0, 1e-12);
  }
}

TEST(HeldEvents, AgentOnACellWallActsWhenTheCrossingComesFirst) {
  // A lone disk at x = 2.5 moving at +1 in a periodic 20 × 20 box of width-1 cells reaches
  // the plane x = 10, a cell wall, at t = 7.5 + 20 k, in a tie with its crossing into the
  // next cell, which goes first.
  for (auto cal : {ed::CalendarKind::cell_heap, ed::CalendarKind::bucket}) {
    ed::Config c;
    c.lx = c.ly = 20.0;
    c.calendar = cal;
    std::vector<ed::DiskInit> d(1);
    d[0].r = {2.5, 5.0};
    d[0].v = {1.0, 0.0};
    ed::Simulation sim(c, d);
    ASSERT_EQ(sim.state().grid.width(), 1.0);
    // The probe ignores a disk on its plane (within 1e−9), taking it for one just recorded:
    // it must not be asked again when the crossing at the same moment goes first.
    auto* plane = static_cast<grainflow::test::PlaneProbe*>(
        sim.add_agent(std::make_unique<grainflow::test::PlaneProbe>(10.0)));
    plane->recording = true;
    sim.run_until(70.0);
    ASSERT_EQ(plane->times.size(), 4u);
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(plane->times[k], 7.5 + 20.0 * k, 1e-9) << k;
  }
}
