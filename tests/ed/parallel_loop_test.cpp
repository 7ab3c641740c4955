// The two-lane ED loop (ParallelLoop): the same bits on one thread and on two, physics of
// the one loop within statistics, and clear refusals of what it does not run.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/core/rng.hpp"
#include "engine/ed/circular_obstacle.hpp"
#include "engine/ed/dense_stream.hpp"
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

// Disks (as stored), clock, epoch, counts and books of two simulations, bit for bit (the
// books' sums too: a lane that took an event late sums them again in the order of one
// loop, LaneBookLog; without that, the inelastic streams below part in their last bits).
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
  EXPECT_TRUE(same_bits(a.stats().virial, b.stats().virial)) << a.stats().virial - b.stats().virial;
  EXPECT_TRUE(same_bits(a.stats().virial_xy, b.stats().virial_xy));
  EXPECT_TRUE(same_bits(a.stats().kT_integral, b.stats().kT_integral)) << a.stats().kT_integral - b.stats().kT_integral;
  EXPECT_TRUE(same_bits(a.stats().kinetic_integral_xy, b.stats().kinetic_integral_xy));
  EXPECT_TRUE(same_bits(a.state().kinetic(), b.state().kinetic())) << a.state().kinetic() - b.state().kinetic();
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

// An agent that meets disk 0 at t = 1 and fails there (an error in a lane's thread).
class FailsAtOne final : public ed::ParticleAgent {
public:
  std::string_view name() const override { return "fails at one"; }
  void cells(const ed::CellGrid& g, std::vector<int>& out) const override {
    for (int c = 0; c < g.size(); ++c) out.push_back(c);
  }
  double event_time(const ed::SystemState&, int i, const ed::DiskNow& d) const override {
    return i == 0 && d.t < 1.0 ? 1.0 - d.t : ed::kNever;
  }
  void action(ed::SystemState&, int) override { throw grainflow::Error("the agent failed"); }
  void save(grainflow::io::ArchiveWriter&) const override {}
  void load(grainflow::io::ArchiveReader&) override {}
};

// The seed's dune in small (scenes/dune_quick.toml): a dense stream (dispenser piston and
// recharge, filter freezing and removing disks) past a no-slip obstacle whose random flips
// come from one stream, elastic to t_cool, then inelastic with the TC model (a phase).
struct Dune {
  std::unique_ptr<ed::Simulation> sim;
  ed::CircularObstacle* obstacle = nullptr;
  Dune(int lanes, int threads, double e) : e_(e) {
    ed::Config c;
    c.lx = 90.0;
    c.ly = 48.0;
    c.area_fraction = 0.65;
    c.kT = 0.02;
    c.stream = {0.1, 0.0};
    c.periodic_x = false;
    c.open_x = true;
    c.seed = 8;
    c.lanes = lanes;
    c.threads = threads;
    sim = std::make_unique<ed::Simulation>(c);
    ed::ObstacleConfig oc;
    oc.centre = {30.0, 24.0};  // on the cut between the lanes
    oc.radius = 6.0;
    oc.boundary = ed::ObstacleBoundary::flip;
    oc.seed = grainflow::core::substream_seed(c.seed, 1);
    obstacle = &sim->add_obstacle(oc);
    ed::DenseStreamConfig d;
    d.U = 0.1;
    d.kT = c.kT;
    d.area_fraction = 0.65;
    d.filter_distance = 3.0;
    d.local_kT = true;
    d.seed = grainflow::core::substream_seed(c.seed, 2);
    ed::add_dense_stream(*sim, d);
  }
  void run(double t_cool, double t_end) {
    sim->run_until(t_cool);
    sim->set_restitution(e_);
    sim->set_time_cutoff(1e-4, 1e-5);
    sim->run_until(t_end);
  }

private:
  double e_;
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

TEST(EdParallelLoop, AStreamPastAnObstacleWithTheTcModelGivesTheSameBitsOnOneThreadAndTwo) {
  // Every agent of the dune runs in the lanes: the piston (an edge of both bands), the
  // recharge adding disks at stops, the filter freezing and removing them, the obstacle
  // drawing random flips, and the TC model with its overlap removals.
  // Strongly inelastic (e = 0.3): the cooled stream clusters in the obstacle's wake, on
  // the cut, where chains of collisions run fast (without the late-event check, the two
  // threads parted from the merged order here at t ≈ 46).
  Dune one(2, 1, 0.3), two(2, 2, 0.3);
  one.run(30.0, 90.0);
  two.run(30.0, 90.0);
  expect_identical(*one.sim, *two.sim);
  const ed::Stats &a = one.sim->stats(), &b = two.sim->stats();
  EXPECT_EQ(a.agent_events, b.agent_events);
  EXPECT_EQ(a.inserted, b.inserted);
  EXPECT_EQ(a.removed, b.removed);
  EXPECT_EQ(a.removed_overlap, b.removed_overlap);
  EXPECT_EQ(a.tc_elastic, b.tc_elastic);
  EXPECT_EQ(one.obstacle->hits(), two.obstacle->hits());
  std::printf("agent events %llu, inserted %llu, removed %llu, TC-elastic %llu, obstacle hits %llu; runs %llu, "
              "done again %llu\n",
              (unsigned long long)b.agent_events, (unsigned long long)b.inserted, (unsigned long long)b.removed,
              (unsigned long long)b.tc_elastic, (unsigned long long)two.obstacle->hits(),
              (unsigned long long)two.sim->lane_runs().runs, (unsigned long long)two.sim->lane_runs().redone);
  EXPECT_GT(b.inserted, 300u);
  EXPECT_GT(b.removed, 250u);
  EXPECT_GT(two.obstacle->hits(), 300u);
  EXPECT_GT(b.tc_elastic, 0u);
  EXPECT_GT(two.sim->min_gap(), -1e-9);
}

TEST(EdParallelLoop, OverlapRemovalsOfTheTcModelGiveTheSameBitsOnOneThreadAndTwo) {
  // tc_model_test's collapsing box (e = 0.5, τ_TC from 0 in steps): its removals come in
  // events a lane took as inner, which wait for the other lane's order and are done then.
  auto make = [](int threads) {
    ed::Config c = ed::test::collapsing_box();
    c.lanes = 2;
    c.threads = threads;
    return std::make_unique<ed::Simulation>(c);
  };
  auto one = make(1), two = make(2);
  for (auto* s : {one.get(), two.get()}) {
    bool reached = false;
    for (int k = 0; k < 200 && !reached; ++k) reached = s->run_until(80.0, 500'000);
    ASSERT_TRUE(reached);
  }
  expect_identical(*one, *two);
  EXPECT_GE(two->overlap_removals(), 1u);
  EXPECT_EQ(one->overlap_removals(), two->overlap_removals());
  EXPECT_EQ(one->tau_tc(), two->tau_tc());
  std::printf("removals %llu, runs %llu, done again %llu\n", (unsigned long long)two->overlap_removals(),
              (unsigned long long)two->lane_runs().runs, (unsigned long long)two->lane_runs().redone);
}

TEST(EdParallelLoop, AnOverlapFoundInAnInnerEventIsRemovedInTheOrderOfOneThread) {
  // tc_model_test's constructed overlap (disk 0 moved 0.1 σ into disk 1, approaching) deep
  // in lane 0's band, beside a gas in lane 1's: on two threads the lane meets the removal
  // in an event it took as inner, puts it off until the other lane is past it, then
  // removes the disk as on one thread.
  auto make = [](int threads) {
    ed::Config c;
    c.lx = c.ly = 40.0;
    c.e = 0.5;
    c.tau_tc = 0.01;
    c.tau_tc_step = 0.005;
    c.lanes = 2;
    c.threads = threads;
    std::vector<ed::DiskInit> d{ed::test::disk_at(4.3, 10.0, 0.1, 0.0), ed::test::disk_at(5.5, 10.0, -0.1, 0.0)};
    for (int i = 0; i < 30; ++i)
      d.push_back(ed::test::disk_at(2.0 + 1.2 * i, 30.0, i % 2 ? 0.3 : -0.3, i % 3 ? 0.2 : -0.2));
    auto sim = std::make_unique<ed::Simulation>(c, d);
    sim->state().disk[0].x = 4.6;  // same cell: centres 0.9 apart
    sim->state().repredict(0);
    return sim;
  };
  auto one = make(1), two = make(2);
  one->run_until(30.0);
  two->run_until(30.0);
  expect_identical(*one, *two);
  EXPECT_EQ(two->overlap_removals(), 1u);
  EXPECT_FALSE(two->present(1));
  ASSERT_EQ(two->overlap_log().size(), 1u);
  EXPECT_EQ(two->overlap_log()[0].t, 0.0);
  EXPECT_DOUBLE_EQ(two->tau_tc(), 0.015);
  EXPECT_GT(two->stats().collisions, 10u);
}

TEST(EdParallelLoop, AStreamPastAnObstacleResumesFromACheckpointWithTheSameBits) {
  // The agents' own state (random streams, the piston's cycle, the filter's arrivals) and
  // the disks the stream added and removed come back with the checkpoint.
  Dune run(2, 2, 0.5), resumed(2, 1, 0.5);
  run.sim->run_until(40.0);
  grainflow::io::ArchiveWriter w;
  run.sim->save_state(w);
  const std::string bytes = w.take();
  grainflow::io::ArchiveReader r(bytes, "checkpoint");
  resumed.sim->load_state(r);
  for (Dune* d : {&run, &resumed}) {
    d->sim->set_restitution(0.5);
    d->sim->set_time_cutoff(1e-4, 1e-5);
    d->sim->run_until(80.0);
  }
  expect_identical(*run.sim, *resumed.sim);
  EXPECT_EQ(run.obstacle->hits(), resumed.obstacle->hits());
  EXPECT_EQ(run.sim->stats().inserted, resumed.sim->stats().inserted);
}

TEST(EdParallelLoop, AStreamPastAnObstacleMatchesTheOneLoopInStatistics) {
  // Two lanes move the positions' epoch at other times than one loop, so the runs part in
  // their bits; what they measure must agree: the stream's density and velocity downstream
  // of the obstacle, the obstacle's hits, the disks the dispenser fed.
  struct Measured {
    double n = 0.0, vx = 0.0, hits = 0.0, inserted = 0.0;
  };
  auto measure = [](int lanes) {
    Dune d(lanes, lanes, 1.0);
    d.sim->run_until(60.0);  // the stream set up around the obstacle
    const auto hits0 = d.obstacle->hits();
    const auto in0 = d.sim->stats().inserted;
    Measured m;
    int samples = 0;
    for (double t = 65.0; t <= 200.0; t += 5.0, ++samples) {
      d.sim->run_until(t);
      d.sim->synchronise();
      for (int i = 0; i < d.sim->size(); ++i) {
        if (!d.sim->present(i) || d.sim->state().frozen(i)) continue;
        const ed::Disk& k = d.sim->disks()[i];
        if (k.x < 45.0 || k.x > 80.0) continue;
        m.n += 1.0;
        m.vx += k.vx;
      }
    }
    m.vx /= m.n;
    m.n /= samples;
    m.hits = double(d.obstacle->hits() - hits0);
    m.inserted = double(d.sim->stats().inserted - in0);
    return m;
  };
  const Measured one = measure(1), two = measure(2);
  std::printf("one loop: n %.1f, vx %.4f, hits %.0f, inserted %.0f; two lanes: n %.1f, vx %.4f, hits %.0f, "
              "inserted %.0f\n", one.n, one.vx, one.hits, one.inserted, two.n, two.vx, two.hits, two.inserted);
  EXPECT_NEAR(two.n, one.n, 0.01 * one.n);
  EXPECT_NEAR(two.vx, one.vx, 0.1 * 0.1);  // 10 % of U
  EXPECT_NEAR(two.hits, one.hits, 0.1 * one.hits);
  EXPECT_NEAR(two.inserted, one.inserted, 0.02 * one.inserted);
}

TEST(EdParallelLoop, AnErrorInALaneIsThrownToTheCaller) {
  ed::Simulation sim(box(20000, 2, 2));
  sim.add_agent(std::make_unique<FailsAtOne>());
  EXPECT_THROW(sim.run_until(3.0), grainflow::Error);
}
