// The two-lane ED loop (ParallelLoop): the same bits on one thread and on two, physics of
// the one loop within statistics, and clear refusals of what it does not run.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/ed/simulation.hpp"
#include "engine/io/archive.hpp"
#include "tests/ed/periodic_box.hpp"

namespace ed = grainflow::ed;

namespace {

ed::Config box(int n, int lanes, int threads, double eta = 0.65) {
  ed::Config c = ed::test::periodic_box(n, eta, 5);
  c.lanes = lanes;
  c.threads = threads;
  return c;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Disks (as stored), clock, epoch and counts of two simulations, bit for bit; the books to
// round-off (a lane may sum them in another order: ParallelLoop).
void expect_identical(const ed::Simulation& a, const ed::Simulation& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(same_bits(a.time(), b.time()));
  EXPECT_TRUE(same_bits(a.state().epoch(), b.state().epoch()));
  int differ = 0;
  for (int i = 0; i < a.size(); ++i) {
    const ed::Disk &p = a.disks()[i], &q = b.disks()[i];
    differ += !(same_bits(p.x, q.x) && same_bits(p.y, q.y) && same_bits(p.vx, q.vx) && same_bits(p.vy, q.vy));
  }
  EXPECT_EQ(differ, 0);
  EXPECT_EQ(a.stats().events, b.stats().events);
  EXPECT_EQ(a.stats().collisions, b.stats().collisions);
  EXPECT_EQ(a.stats().cell_crossings, b.stats().cell_crossings);
  EXPECT_EQ(a.stats().stale, b.stats().stale);
  EXPECT_NEAR(a.stats().virial, b.stats().virial, 1e-12 * std::abs(b.stats().virial));
  EXPECT_NEAR(a.stats().kT_integral, b.stats().kT_integral, 1e-12 * std::abs(b.stats().kT_integral));
  EXPECT_NEAR(a.state().kinetic(), b.state().kinetic(), 1e-12 * b.state().kinetic());
}

// A timer that every `dt` reverses the velocity of every seventh disk (so the lanes must
// predict them again) and records Σ x now over all disks (what a sampler reads).
class Reverser final : public ed::TimerAgent {
public:
  explicit Reverser(double dt) : dt_(dt), next_(dt) {}
  std::string_view name() const override { return "reverser"; }
  double event_time(const ed::SystemState&) const override { return next_; }
  void action(ed::SystemState& s) override {
    double sum = 0.0;
    for (int i = 0; i < s.size(); ++i) sum += s.position_now(i).x();
    seen.push_back(sum);
    for (int i = 0; i < s.size(); i += 7) s.set_velocity(i, -s.disk[i].vx, -s.disk[i].vy);
    next_ += dt_;
  }
  void save(grainflow::io::ArchiveWriter&) const override {}
  void load(grainflow::io::ArchiveReader&) override {}
  std::vector<double> seen;

private:
  double dt_, next_;
};

}  // namespace

TEST(EdParallelLoop, TwoThreadsGiveTheBitsOfOne) {
  const int n = 20000;
  ed::Simulation one(box(n, 2, 1)), two(box(n, 2, 2));
  // Several stops, rebases among them, and about 25 collisions a disk.
  for (double t : {5.0, 20.0, 21.5, 60.0}) {
    one.run_until(t);
    two.run_until(t);
    expect_identical(one, two);
  }
  EXPECT_GT(two.stats().collisions, 20ull * n);
}

TEST(EdParallelLoop, TimersActAtStopsWithTheSameBits) {
  const int n = 20000;
  ed::Simulation one(box(n, 2, 1)), two(box(n, 2, 2));
  Reverser& r1 = one.emplace_timer<Reverser>(0.7);
  Reverser& r2 = two.emplace_timer<Reverser>(0.7);
  one.run_until(15.0);
  two.run_until(15.0);
  expect_identical(one, two);
  ASSERT_EQ(r1.seen.size(), 21u);  // t = 0.7, 1.4, …, 14.7
  EXPECT_EQ(r1.seen, r2.seen);
  EXPECT_EQ(one.stats().timer_events, 21u);
  // The reversed disks were predicted again: a stale prediction would let disks overlap.
  EXPECT_GT(two.min_gap(), -1e-9);
}

TEST(EdParallelLoop, ResumesFromACheckpointWithTheSameBits) {
  const int n = 20000;
  ed::Simulation run(box(n, 2, 2)), resumed(box(n, 2, 1));
  run.run_until(3.0);
  grainflow::io::ArchiveWriter w;
  run.save_state(w);
  const std::string bytes = w.take();
  grainflow::io::ArchiveReader r(bytes, "checkpoint");
  resumed.load_state(r);
  // Several rebase stops later, planned afresh by the resumed run.
  run.run_until(12.0);
  resumed.run_until(12.0);
  expect_identical(run, resumed);
}

TEST(EdParallelLoop, MatchesTheOneLoopInStatistics) {
  // Equation of state and mean free time of the one loop, and energy conservation.
  const int n = 20000;
  ed::Simulation lanes(box(n, 2, 2, 0.5)), one(box(n, 1, 1, 0.5));
  for (ed::Simulation* s : {&lanes, &one}) {
    s->run_until(20.0);  // melt
    s->reset_measurements();
    s->run_until(120.0);
  }
  const ed::Observables a = lanes.observables(), b = one.observables();
  EXPECT_NEAR(a.compressibility, b.compressibility, 0.01 * b.compressibility);
  EXPECT_NEAR(a.mean_free_time, b.mean_free_time, 0.01 * b.mean_free_time);
  EXPECT_NEAR(a.kT, 0.02, 1e-9);
  // The books the lanes kept against the disks themselves, and the energy they started with.
  double kin = 0.0;
  for (int i = 0; i < lanes.size(); ++i) {
    const ed::Disk& d = lanes.disks()[i];
    kin += 0.5 * lanes.state().body[i].m * (d.vx * d.vx + d.vy * d.vy);
  }
  EXPECT_NEAR(lanes.state().kinetic(), kin, 1e-9 * kin);
  EXPECT_NEAR(kin, one.state().kinetic(), 1e-9 * kin);
}

TEST(EdParallelLoop, RefusesWhatItDoesNotRun) {
  ed::Config walls = box(20000, 2, 2);
  walls.periodic_y = false;
  EXPECT_THROW(ed::Simulation{walls}, grainflow::Error);
  ed::Config small = box(100, 2, 2);  // 11 rows of cells: the bands would have no inner rows
  EXPECT_THROW(ed::Simulation{small}, grainflow::Error);
  ed::Config three = box(20000, 2, 3);
  EXPECT_THROW(ed::Simulation{three}, grainflow::Error);
  ed::Config one_lane_two_threads = box(20000, 1, 2);
  EXPECT_THROW(ed::Simulation{one_lane_two_threads}, grainflow::Error);
  // A collision observer would never be called: refused at the next run.
  ed::Simulation traced(box(20000, 2, 2));
  traced.set_collision_observer([](const ed::CollisionRecord&) {});
  EXPECT_THROW(traced.run_until(1.0), grainflow::Error);
  EXPECT_THROW(traced.advance(10), grainflow::Error);
}
