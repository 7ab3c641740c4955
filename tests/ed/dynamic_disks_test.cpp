// Disks that enter, leave and freeze during a run (open stream boundaries, seed 003
// §3.2–3.3): against a brute-force next-collision reference over the disks present, both
// calendars agreeing collision by collision, no overlap, no event for an absent disk,
// exact energy/momentum books, and the frozen (infinitely heavy) disk of the filter.
#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include <gtest/gtest.h>

#include "engine/core/error.hpp"
#include "engine/core/rng.hpp"
#include "engine/ed/pair_collision_time.hpp"
#include "engine/ed/simulation.hpp"
#include "tests/ed/churn.hpp"
#include "engine/io/archive.hpp"

namespace ed = grainflow::ed;

namespace {

// A timer that runs a function at fixed intervals (the test's stand-in for inlet/outlet).
class EveryTimer final : public ed::TimerAgent {
public:
  EveryTimer(double t0, double dt, std::function<void(ed::SystemState&)> f) : next_(t0), dt_(dt), f_(std::move(f)) {}
  std::string_view name() const override { return "test timer"; }
  double event_time(const ed::SystemState&) const override { return next_; }
  void action(ed::SystemState& s) override {
    ++calls;
    next_ += dt_;
    f_(s);
  }
  // Its clock and call count. The function's own captures (the churn's random stream) are
  // the test's code, out of the engine's sight: these tests take no checkpoints.
  void save(grainflow::io::ArchiveWriter& w) const override {
    w.pod(next_);
    w.pod(calls);
  }
  void load(grainflow::io::ArchiveReader& r) override {
    r.pod(next_);
    r.pod(calls);
  }
  int calls = 0;

private:
  double next_, dt_;
  std::function<void(ed::SystemState&)> f_;
};

struct RefEvent {
  double dt;
  int i, j;
};
// Next collision among the disks present (periodic in both axes, 9 images).
RefEvent brute_force_next(const ed::Simulation& sim) {
  const auto& d = sim.disks();
  const auto& rb = sim.bodies();
  const auto& c = sim.config();
  RefEvent best{ed::kNever, -1, -1};
  for (int i = 0; i < sim.size(); ++i) {
    if (!sim.present(i)) continue;
    for (int j = i + 1; j < sim.size(); ++j) {
      if (!sim.present(j)) continue;
      for (int kx = -1; kx <= 1; ++kx)
        for (int ky = -1; ky <= 1; ++ky) {
          const double t = ed::pair_collision_time(d[i].x - d[j].x - kx * c.lx, d[i].y - d[j].y - ky * c.ly,
                                                   d[i].vx - d[j].vx, d[i].vy - d[j].vy, rb[i].r + rb[j].r);
          if (t < best.dt) best = {t, i, j};
        }
    }
  }
  return best;
}

// Random changes: removes a random present disk, adds disks at random free places (more
// adds than removals at first, so the slot arrays must grow mid-run), freezes one now and then.
struct Churn {
  grainflow::core::Rng rng{99};
  int actions = 0;
  void operator()(ed::SystemState& s) {
    ++actions;
    ed::test::churn(s, rng, actions, actions < 40 ? 2 : 1);
  }
};

ed::Config box(ed::CalendarKind cal) {
  ed::Config c;
  c.lx = 9.0;
  c.ly = 7.5;
  c.area_fraction = 0.35;
  c.kT = 1.0;
  c.seed = 5;
  c.calendar = cal;
  return c;
}

// Exact books: mobile disks only.
void expect_books_exact(const ed::Simulation& sim) {
  const double k = sim.state().kinetic() + sim.state().rotational();
  EXPECT_NEAR(k, sim.kinetic_energy(), 1e-9 * std::max(1.0, sim.kinetic_energy()));
  EXPECT_NEAR(sim.state().momentum().x(), sim.momentum().x(), 1e-9);
  EXPECT_NEAR(sim.state().momentum().y(), sim.momentum().y(), 1e-9);
}

void check_churn_against_brute_force(ed::CalendarKind cal, std::vector<ed::CollisionRecord>* trace) {
  ed::Simulation sim(box(cal));
  const int n0 = sim.size();
  auto& timer = sim.emplace_timer<EveryTimer>(0.05, 0.05, Churn{});
  ed::CollisionRecord last{-1, -1, 0.0};
  int absent_hits = 0;
  sim.set_collision_observer([&](const ed::CollisionRecord& r) {
    last = r;
    if (!sim.present(r.i) || !sim.present(r.j)) ++absent_hits;
    if (trace) trace->push_back(r);
  });
  int checked = 0;
  for (int k = 0; k < 2500; ++k) {
    sim.synchronise();
    const RefEvent ref = brute_force_next(sim);
    const double t_timer = timer.event_time(sim.state());
    const double t_ref = sim.time() + ref.dt;
    const auto c0 = sim.stats().collisions;
    const int calls0 = timer.calls;
    while (sim.stats().collisions == c0 && timer.calls == calls0) ASSERT_EQ(sim.advance(1), 1u);
    if (t_ref < t_timer - 1e-9) {
      ASSERT_EQ(timer.calls, calls0) << "event " << k;
      ASSERT_EQ(std::min(last.i, last.j), ref.i) << "event " << k;
      ASSERT_EQ(std::max(last.i, last.j), ref.j) << "event " << k;
      ASSERT_NEAR(last.t, t_ref, 1e-9) << "event " << k;
      ++checked;
    } else if (t_timer < t_ref - 1e-9) {
      ASSERT_EQ(sim.stats().collisions, c0) << "event " << k << ": a collision before the timer";
    }
    ASSERT_GE(sim.min_gap(), -1e-9) << "event " << k;
  }
  EXPECT_EQ(absent_hits, 0);
  EXPECT_GT(checked, 1500);
  EXPECT_GT(timer.calls, 60);
  EXPECT_GT(sim.size(), n0) << "the slot arrays never grew";
  EXPECT_GT(sim.state().frozen_count(), 0);
  EXPECT_EQ(sim.stats().inserted - sim.stats().removed, std::uint64_t(sim.count() - n0));
  expect_books_exact(sim);
  // The slots and the cell map agree.
  int present = 0;
  for (int i = 0; i < sim.size(); ++i) present += sim.present(i);
  EXPECT_EQ(present, sim.count());
}

}  // namespace

TEST(DynamicDisks, ChurnAgainstBruteForceBucket) { check_churn_against_brute_force(ed::CalendarKind::bucket, nullptr); }
TEST(DynamicDisks, ChurnAgainstBruteForceCellHeap) {
  check_churn_against_brute_force(ed::CalendarKind::cell_heap, nullptr);
}

TEST(DynamicDisks, CalendarsAgreeWithChurn) {
  std::vector<ed::CollisionRecord> seq[2];
  int k = 0;
  for (auto cal : {ed::CalendarKind::cell_heap, ed::CalendarKind::bucket}) {
    ed::Config c = box(cal);
    c.lx = c.ly = 16.0;
    c.area_fraction = 0.6;
    ed::Simulation sim(c);
    sim.emplace_timer<EveryTimer>(0.02, 0.02, Churn{});
    auto& s = seq[k++];
    sim.set_collision_observer([&](const ed::CollisionRecord& r) { s.push_back(r); });
    while (s.size() < 30000) sim.advance(1000);
    s.resize(30000);
    EXPECT_GE(sim.min_gap(), -1e-9);
    expect_books_exact(sim);
  }
  for (std::size_t n = 0; n < seq[0].size(); ++n) {
    ASSERT_EQ(seq[0][n].i, seq[1][n].i) << n;
    ASSERT_EQ(seq[0][n].j, seq[1][n].j) << n;
    ASSERT_NEAR(seq[0][n].t, seq[1][n].t, 1e-9) << n;
  }
}

TEST(DynamicDisks, FrozenDiskIsAnInfinitelyHeavyMovingWall) {
  // Head-on: mobile disk at x = 2 with v = (1, 0); disk at x = 4 frozen at v = (0.5, 0).
  // Contact when the gap 1 closes at relative speed 0.5 (t = 2); in the frozen frame the
  // mobile disk's +0.5 becomes −0.5, i.e. 0 in the lab. The frozen disk keeps 0.5.
  ed::Config c;
  c.lx = c.ly = 10.0;
  std::vector<ed::DiskInit> d(2);
  d[0].r = {2.0, 5.0};
  d[0].v = {1.0, 0.0};
  d[1].r = {4.0, 5.0};
  d[1].v = {-3.0, 0.0};
  ed::Simulation sim(c, d);
  sim.emplace_timer<EveryTimer>(0.0, ed::kNever, [](ed::SystemState& s) { s.freeze(1, 0.5, 0.0); });
  sim.run_until(1e-12);
  EXPECT_TRUE(sim.state().frozen(1));
  EXPECT_EQ(sim.state().mobile_count(), 1);
  EXPECT_NEAR(sim.state().kinetic(), 0.5, 1e-15);  // the frozen disk is out of the books
  EXPECT_NEAR(sim.state().momentum().x(), 1.0, 1e-15);
  sim.run_until(3.0);
  EXPECT_EQ(sim.stats().collisions, 1u);
  EXPECT_NEAR(sim.disks()[0].vx, 0.0, 1e-12);
  EXPECT_NEAR(sim.disks()[1].vx, 0.5, 1e-15);
  EXPECT_TRUE(std::isfinite(sim.state().kinetic()));
  EXPECT_NEAR(sim.state().kinetic(), 0.0, 1e-12);
  expect_books_exact(sim);
  sim.synchronise();
  EXPECT_NEAR(sim.disks()[0].x, 4.0, 1e-12);  // stopped at the contact point (t = 2)
  EXPECT_NEAR(sim.disks()[1].x, 4.0 + 0.5 * 3.0, 1e-12);
}

TEST(DynamicDisks, ObliqueHitKeepsRelativeSpeedAndReflectsNormalComponent) {
  ed::Config c;
  c.lx = c.ly = 10.0;
  std::vector<ed::DiskInit> d(2);
  d[0].r = {2.0, 5.2};
  d[0].v = {1.0, 0.0};
  d[1].r = {4.0, 5.0};
  ed::Simulation sim(c, d);
  const double ux = 0.25, uy = -0.1;
  sim.emplace_timer<EveryTimer>(0.0, ed::kNever, [&](ed::SystemState& s) { s.freeze(1, ux, uy); });
  ed::CollisionRecord rec{-1, -1, 0};
  sim.set_collision_observer([&](const ed::CollisionRecord& r) { rec = r; });
  sim.run_until(5.0);
  ASSERT_EQ(sim.stats().collisions, 1u);
  // Reconstruct the contact normal and compare with the specular rule in the frozen frame.
  const double t = rec.t;
  const double ax = 2.0 + 1.0 * t, ay = 5.2, bx = 4.0 + ux * t, by = 5.0 + uy * t;
  const double nx = (ax - bx), ny = (ay - by);
  EXPECT_NEAR(std::hypot(nx, ny), 1.0, 1e-12);
  const double cx = 1.0 - ux, cy = 0.0 - uy, cn = cx * nx + cy * ny;
  EXPECT_NEAR(sim.disks()[0].vx, ux + cx - 2 * cn * nx, 1e-12);
  EXPECT_NEAR(sim.disks()[0].vy, uy + cy - 2 * cn * ny, 1e-12);
  EXPECT_EQ(sim.disks()[1].vx, ux);
  EXPECT_EQ(sim.disks()[1].vy, uy);
}

TEST(DynamicDisks, FrozenWallAtRestKeepsMobileEnergyExactly) {
  // A column of disks frozen at rest in a dense periodic box: the mobile disks bounce off
  // them elastically, so their energy is conserved while their momentum is not; no overlap.
  for (auto cal : {ed::CalendarKind::bucket, ed::CalendarKind::cell_heap}) {
    ed::Config c;
    c.lx = 24.0;
    c.ly = 12.0;
    c.area_fraction = 0.65;
    c.calendar = cal;
    ed::Simulation sim(c);
    sim.emplace_timer<EveryTimer>(0.0, ed::kNever, [](ed::SystemState& s) {
      for (int i = 0; i < s.size(); ++i)
        if (s.position_now(i).x() > 10.0 && s.position_now(i).x() < 12.0) s.freeze(i, 0.0, 0.0);
    });
    sim.run_until(1e-9);
    const int frozen = sim.state().frozen_count();
    EXPECT_GT(frozen, 10);
    const double k0 = sim.kinetic_energy();
    EXPECT_NEAR(sim.state().kinetic(), k0, 1e-12 * k0);
    std::uint64_t with_frozen = 0;
    sim.set_collision_observer([&](const ed::CollisionRecord& r) {
      with_frozen += sim.state().frozen(r.i) || sim.state().frozen(r.j);
    });
    sim.advance(300000);
    EXPECT_GT(with_frozen, 1000u);
    EXPECT_NEAR(sim.kinetic_energy(), k0, 1e-9 * k0);
    expect_books_exact(sim);
    EXPECT_GE(sim.min_gap(), -1e-9);
    // No frozen disk moved.
    sim.synchronise();
    for (int i = 0; i < sim.size(); ++i)
      if (sim.state().frozen(i)) {
        EXPECT_EQ(sim.disks()[i].vx, 0.0);
        EXPECT_EQ(sim.disks()[i].vy, 0.0);
      }
    // kT from peculiar velocities of the mobile disks only (Eq. 4.9).
    const grainflow::Vec2 p = sim.momentum();
    const int mobile = sim.count() - frozen;
    EXPECT_NEAR(sim.state().kT(), (k0 - 0.5 * p.squaredNorm() / mobile) / mobile, 1e-9 * k0);
  }
}

TEST(DynamicDisks, AddedDiskRejectedOutsideTheBoxOrTooLarge) {
  ed::Config c;
  c.lx = c.ly = 10.0;
  c.area_fraction = 0.2;
  ed::Simulation sim(c);
  ed::DiskInit bad;
  bad.r = {11.0, 5.0};
  EXPECT_THROW(sim.state().add_disk(bad), grainflow::Error);
  bad.r = {5.0, 5.0};
  bad.radius = 5.0;
  EXPECT_THROW(sim.state().add_disk(bad), grainflow::Error);
}

TEST(DynamicDisks, ChangesMadeBetweenRunsAreSettled) {
  // add_disk/remove_disk/freeze outside any action (e.g. set-up code): the next run picks
  // them up, including a growth of the slot arrays.
  for (auto cal : {ed::CalendarKind::bucket, ed::CalendarKind::cell_heap}) {
    ed::Config c = box(cal);
    c.lx = c.ly = 12.0;
    c.area_fraction = 0.2;
    ed::Simulation sim(c);
    sim.run_until(1.0);
    const int slots0 = sim.size();
    Churn churn;
    for (int k = 0; k < 60; ++k) churn(sim.state());
    EXPECT_GT(sim.size(), slots0);
    sim.run_until(30.0);
    EXPECT_GE(sim.min_gap(), -1e-9);
    expect_books_exact(sim);
    EXPECT_GT(sim.stats().collisions, 1000u);
  }
}
