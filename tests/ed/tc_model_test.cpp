// The TC (time cutoff) model of Luding & McNamara 1998 in the ED engine (seed 003 ch. 5):
// a disk–disk collision is elastic in its normal part when either party's previous
// collision is less than τ_TC ago, and dissipates exactly (1 − e²)/4 · m v_n² (equal
// masses) otherwise; a numerical overlap removes the offending disk, logs it and raises
// τ_TC by its step; an inelastic box with the model keeps advancing where one without it
// collapses (CollapseGuard); elastic runs never touch it; homogeneous cooling follows
// Haff's law from an equilibrated elastic start.
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "engine/core/error.hpp"
#include "engine/ed/simulation.hpp"
#include "tests/ed/periodic_box.hpp"

namespace ed = grainflow::ed;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
using ed::test::disk_at;

// One collision as the observer saw it: its energy change and the normal relative speed
// before it.
struct Seen {
  double t, dE, vn;
};

// Three disks on a line (y = 10) of a 20 × 20 periodic box: A (id a) at x = 2 moving +1
// hits B at rest at x = 4 (t = 1, v_n = 1); B, now at (1 + e)/2 = 0.75, hits C at rest at
// 5.05 at t = 1 + 0.05/0.75; A at (1 − e)/2 = 0.25 catches B again at t = 1.2 (e = 0.5 and
// the B–C collision elastic) — each energy change recorded. ids: the slots of A, B, C.
std::vector<Seen> three_on_a_line(double e, double tau, const int (&ids)[3]) {
  ed::Config c;
  c.lx = c.ly = 20.0;
  c.e = e;
  c.tau_tc = tau;
  std::vector<ed::DiskInit> d(3);
  d[ids[0]] = disk_at(2.0, 10.0, 1.0, 0.0);
  d[ids[1]] = disk_at(4.0, 10.0, 0.0, 0.0);
  d[ids[2]] = disk_at(5.05, 10.0, 0.0, 0.0);
  ed::Simulation sim(c, d);
  std::vector<Seen> seen;
  double k_before = sim.kinetic_energy();
  std::vector<double> vx = {d[0].v.x(), d[1].v.x(), d[2].v.x()};
  sim.set_collision_observer([&](const ed::CollisionRecord& r) {
    const double k = sim.kinetic_energy();
    const double vn = std::abs(vx[r.i] - vx[r.j]);  // along the line: the normal component
    seen.push_back({r.t, k - k_before, vn});
    k_before = k;
    for (int i = 0; i < 3; ++i) vx[i] = sim.disks()[i].vx;
  });
  sim.run_until(2.0);
  return seen;
}

}  // namespace

// The rule on a controlled sequence, in three numberings (ids decide nothing): pinned with
// ΔE = −(1 − e²)/4 · v_n². (The dense box below has the recent party on either side.)
TEST(TcModel, CollisionWithinTheCutoffOfEitherPartyIsElasticOtherwiseDissipatesExactly) {
  const double e = 0.5, loss = (1.0 - e * e) / 4.0;
  for (const auto& ids : {std::to_array({0, 1, 2}), std::to_array({2, 1, 0}), std::to_array({1, 2, 0})}) {
    const int order[3] = {ids[0], ids[1], ids[2]};
    SCOPED_TRACE(::testing::Message() << "ids A, B, C = " << ids[0] << ", " << ids[1] << ", " << ids[2]);
    // τ = 0.1: B's collision with A was 1/15 ago when it meets C: elastic.
    const std::vector<Seen> s = three_on_a_line(e, 0.1, order);
    ASSERT_EQ(s.size(), 3u);
    EXPECT_NEAR(s[0].t, 1.0, 1e-12);
    EXPECT_NEAR(s[0].vn, 1.0, 1e-12);
    EXPECT_NEAR(s[0].dE, -loss * 1.0, 1e-14);         // first collision of both: inelastic
    EXPECT_NEAR(s[1].t, 1.0 + 0.05 / 0.75, 1e-12);
    EXPECT_NEAR(s[1].vn, 0.75, 1e-12);
    EXPECT_NEAR(s[1].dE, 0.0, 1e-15);                 // B collided 0.0667 < τ ago: elastic
    EXPECT_NEAR(s[2].t, 1.2, 1e-12);                  // A (0.25) reaches B, now at rest
    EXPECT_NEAR(s[2].vn, 0.25, 1e-12);
    EXPECT_NEAR(s[2].dE, -loss * 0.25 * 0.25, 1e-15);  // B's last one 0.133 > τ ago
    // τ = 0.05 < 1/15: the B–C collision dissipates like any other.
    const std::vector<Seen> u = three_on_a_line(e, 0.05, order);
    ASSERT_GE(u.size(), 2u);
    EXPECT_NEAR(u[1].dE, -loss * 0.75 * 0.75, 1e-15);
  }
}

// A frozen (infinitely heavy) disk is a wall to the TC model: only the mobile disk's clock
// counts, and the collision with it sets that clock. A (x = 8, +1) hits the frozen F at
// x = 10 at t = 1: its first collision, inelastic (ΔE = −(1 − e²)/2 · m v_n² against an
// infinite mass); A (−0.5) then meets B (x = 6.5, +1) at t = 4/3, 1/3 < τ after: elastic,
// they exchange; A (+1) hits F again at t = 1.5, 1/6 < τ after its collision with B: elastic.
TEST(TcModel, AFrozenDiskIsAWallToTheCutoff) {
  ed::Config c;
  c.lx = c.ly = 20.0;
  c.e = 0.5;
  c.tau_tc = 0.5;
  ed::Simulation sim(c, {disk_at(8.0, 10.0, 1.0, 0.0), disk_at(6.5, 10.0, 1.0, 0.0), disk_at(10.0, 10.0, 0.0, 0.0)});
  sim.state().freeze(2, 0.0, 0.0);
  std::vector<Seen> seen;
  double k_before = sim.kinetic_energy();
  sim.set_collision_observer([&](const ed::CollisionRecord& r) {
    const double k = sim.kinetic_energy();
    seen.push_back({r.t, k - k_before, 0.0});
    k_before = k;
  });
  sim.run_until(1.7);
  ASSERT_EQ(seen.size(), 3u);
  EXPECT_NEAR(seen[0].t, 1.0, 1e-12);
  EXPECT_NEAR(seen[0].dE, -(1.0 - 0.25) / 2.0, 1e-14);
  EXPECT_NEAR(seen[1].t, 1.0 + 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(seen[1].dE, 0.0, 1e-15);
  EXPECT_NEAR(seen[2].t, 1.5, 1e-12);
  EXPECT_NEAR(seen[2].dE, 0.0, 1e-15);
  EXPECT_EQ(sim.stats().tc_elastic, 2u);
  EXPECT_NEAR(sim.disks()[0].vx, -1.0, 1e-14);
  EXPECT_EQ(sim.state().last_collision[2], -kInf);  // the frozen disk's clock is never set
}

// Every collision of a dense inelastic box against the rule, from the observer's own books:
// elastic (energy kept to round-off, v_n reversed) exactly when either party collided
// less than τ ago — both the firing entry and its partner being that party occur —, else
// ΔE = −(1 − e²)/4 · v_n² and v_n' = −e v_n.
TEST(TcModel, EveryCollisionOfADenseBoxFollowsTheRule) {
  ed::Config c = ed::test::periodic_box(745, 0.65, 11);
  c.e = 0.6;
  c.tau_tc = 0.05;  // ≈ 0.1 mean free time: many TC-elastic collisions
  ed::Simulation sim(c);
  const int n = sim.size();
  const double L = c.lx, tau = c.tau_tc, e = c.e;
  std::vector<double> vx(n), vy(n), last(n, -kInf);
  for (int i = 0; i < n; ++i) vx[i] = sim.disks()[i].vx, vy[i] = sim.disks()[i].vy;
  std::uint64_t elastic_i = 0, elastic_j = 0, elastic_both = 0, inelastic = 0;
  double worst_elastic = 0.0, worst_inelastic = 0.0, worst_vn = 0.0;
  sim.set_collision_observer([&](const ed::CollisionRecord& r) {
    const ed::Disk &a = sim.disks()[r.i], &b = sim.disks()[r.j];
    EXPECT_EQ(sim.time(), r.t);  // reported at the collision: positions now are at contact
    const grainflow::Vec2 pa = sim.state().position_now(r.i), pb = sim.state().position_now(r.j);
    double rx = pa.x() - pb.x(), ry = pa.y() - pb.y();
    rx -= L * std::round(rx / L);
    ry -= L * std::round(ry / L);
    const double d = std::hypot(rx, ry), nx = rx / d, ny = ry / d;
    const double vn = (vx[r.i] - vx[r.j]) * nx + (vy[r.i] - vy[r.j]) * ny;
    const double vn1 = (a.vx - b.vx) * nx + (a.vy - b.vy) * ny;
    const double e0 = 0.5 * (vx[r.i] * vx[r.i] + vy[r.i] * vy[r.i] + vx[r.j] * vx[r.j] + vy[r.j] * vy[r.j]);
    const double e1 = 0.5 * (a.vx * a.vx + a.vy * a.vy + b.vx * b.vx + b.vy * b.vy);
    const bool ri = r.t - last[r.i] < tau, rj = r.t - last[r.j] < tau;
    if (ri || rj) {
      (ri && rj ? elastic_both : ri ? elastic_i : elastic_j)++;
      worst_elastic = std::max(worst_elastic, std::abs(e1 - e0) / e0);
      worst_vn = std::max(worst_vn, std::abs(vn1 + vn) / std::abs(vn));
    } else {
      ++inelastic;
      const double expected = -(1.0 - e * e) / 4.0 * vn * vn;
      worst_inelastic = std::max(worst_inelastic, std::abs((e1 - e0) - expected) / std::abs(expected));
      worst_vn = std::max(worst_vn, std::abs(vn1 + e * vn) / std::abs(vn));
    }
    vx[r.i] = a.vx, vy[r.i] = a.vy, vx[r.j] = b.vx, vy[r.j] = b.vy;
    last[r.i] = last[r.j] = r.t;
  });
  sim.run_until(100.0);
  std::printf("  %llu inelastic, %llu TC-elastic (recent: firing entry %llu, partner %llu, both %llu); worst relative "
              "errors: elastic ΔE %.2g, inelastic ΔE %.2g, v_n' %.2g\n",
              (unsigned long long)inelastic, (unsigned long long)(elastic_i + elastic_j + elastic_both),
              (unsigned long long)elastic_i, (unsigned long long)elastic_j, (unsigned long long)elastic_both,
              worst_elastic, worst_inelastic, worst_vn);
  EXPECT_GT(inelastic, 10000u);
  EXPECT_GT(elastic_i, 300u);
  EXPECT_GT(elastic_j, 30u);
  EXPECT_EQ(sim.stats().tc_elastic, elastic_i + elastic_j + elastic_both);
  EXPECT_EQ(sim.stats().collisions, inelastic + sim.stats().tc_elastic);
  EXPECT_LT(worst_elastic, 1e-12);
  EXPECT_LT(worst_inelastic, 1e-9);
  EXPECT_LT(worst_vn, 1e-9);
  EXPECT_EQ(sim.overlap_removals(), 0u);
}

// Elastic runs never read or write the TC state: a cutoff configured with e = 1 leaves
// every bit as without it, and the last-collision array is never allocated.
TEST(TcModel, ElasticRunsAreUntouched) {
  ed::Config c = ed::test::periodic_box(745, 0.65, 4);
  ed::Simulation plain(c);
  c.tau_tc = 0.1;
  c.tau_tc_step = 0.01;
  ed::Simulation with_cutoff(c);
  EXPECT_FALSE(with_cutoff.time_cutoff_on());
  plain.run_until(30.0);
  with_cutoff.run_until(30.0);
  ASSERT_EQ(plain.size(), with_cutoff.size());
  EXPECT_EQ(std::memcmp(plain.disks().data(), with_cutoff.disks().data(), sizeof(ed::Disk) * plain.disks().size()), 0);
  EXPECT_EQ(plain.stats().events, with_cutoff.stats().events);
  EXPECT_TRUE(with_cutoff.state().last_collision.empty());
  EXPECT_EQ(with_cutoff.stats().tc_elastic, 0u);
  EXPECT_EQ(with_cutoff.tau_tc(), 0.1);
}

// A constructed overlap: disk A moved 0.1 σ into B, approaching. With TC on the collision
// found overlapping removes the offender (neither collided before: the higher id), logs it
// at its position, raises τ_TC by the step, and the run goes on; the same state elastic is
// left alone (the pair bounces apart as before).
TEST(TcModel, AnOverlapRemovesTheDiskLogsItAndRaisesTheCutoff) {
  for (double e : {0.5, 1.0}) {
    SCOPED_TRACE(::testing::Message() << "e = " << e);
    ed::Config c;
    c.lx = c.ly = 10.0;
    c.e = e;
    c.tau_tc = 0.01;
    c.tau_tc_step = 0.005;
    ed::Simulation sim(c, {disk_at(4.3, 5.0, 0.1, 0.0), disk_at(5.5, 5.0, -0.1, 0.0),  // A, B
                           disk_at(2.0, 8.0, 0.5, 0.0), disk_at(3.5, 8.0, -0.5, 0.0)});  // meet at t = 0.5
    sim.state().disk[0].x = 4.6;  // same cell [4, 5): centres 0.9 apart
    sim.state().repredict(0);
    const auto collisions0 = sim.stats().collisions;
    ASSERT_TRUE(sim.run_until(2.0, 100000));
    EXPECT_EQ(sim.time(), 2.0);
    if (e < 1.0) {
      EXPECT_EQ(sim.overlap_removals(), 1u);
      EXPECT_EQ(sim.count(), 3);
      EXPECT_FALSE(sim.present(1));
      ASSERT_EQ(sim.overlap_log().size(), 1u);
      const ed::OverlapRemoval& r = sim.overlap_log()[0];
      EXPECT_EQ(r.t, 0.0);
      EXPECT_EQ(r.id, 1);
      EXPECT_EQ(r.x, 5.5);
      EXPECT_EQ(r.y, 5.0);
      EXPECT_DOUBLE_EQ(r.tau_tc, 0.015);
      EXPECT_DOUBLE_EQ(sim.tau_tc(), 0.015);
      EXPECT_EQ(sim.stats().removed, 0u);  // not an outlet's removal
      EXPECT_EQ(sim.stats().collisions - collisions0, 1u);  // the far pair, inelastically
      EXPECT_GE(sim.min_gap(), 0.0);
    } else {
      EXPECT_EQ(sim.overlap_removals(), 0u);
      EXPECT_EQ(sim.count(), 4);
      EXPECT_EQ(sim.tau_tc(), 0.01);
      EXPECT_EQ(sim.stats().collisions - collisions0, 2u);
    }
  }
}

// Seed 003 ch. 5's procedure: start with no cutoff and a step. In this e = 0.5 box an
// inelastic collision comes at an interval below the clock's precision at t ≈ 35: it
// removes the offending disk, τ_TC becomes the step, and the run reaches its target.
// Without the step the box collapses (its clock stalls at t ≈ 98.6): CollapseGuard says so.
TEST(TcModel, ACollapseRemovesTheOffenderRaisesTheCutoffAndTheRunGoesOn) {
  ed::Config c = ed::test::collapsing_box();
  {
    ed::Simulation sim(c);
    const int n0 = sim.count();
    EXPECT_TRUE(sim.time_cutoff_on());
    ed::CollapseGuard guard(2'000'000);
    bool reached = false;
    for (int k = 0; k < 200 && !reached; ++k) {
      reached = sim.run_until(150.0, 500'000);
      ASSERT_FALSE(guard.collapsed(sim)) << "t = " << sim.time();
    }
    ASSERT_TRUE(reached);
    const auto removals = sim.overlap_removals();
    std::printf("  t = 150: %llu removal(s), tau_tc = %g, N %d -> %d, %.0f collisions per disk\n",
                (unsigned long long)removals, sim.tau_tc(), n0, sim.count(), 2.0 * sim.stats().collisions / n0);
    EXPECT_GE(removals, 1u);
    EXPECT_EQ(sim.count(), n0 - int(removals));
    EXPECT_DOUBLE_EQ(sim.tau_tc(), double(removals) * 1e-4);
    ASSERT_EQ(sim.overlap_log().size(), removals);
    double t_prev = 0.0;
    for (const ed::OverlapRemoval& r : sim.overlap_log()) {
      EXPECT_GE(r.t, t_prev);
      EXPECT_GT(r.t, 10.0);
      t_prev = r.t;
      EXPECT_TRUE(r.x >= -1.0 && r.x <= 51.0 && r.y >= -1.0 && r.y <= 51.0) << r.x << ", " << r.y;
      EXPECT_FALSE(sim.present(int(r.id)));
    }
    EXPECT_GT(sim.stats().tc_elastic, 0u);
  }
  {
    c.tau_tc_step = 0.0;  // TC off: the collapse runs its course
    ed::Simulation sim(c);
    EXPECT_FALSE(sim.time_cutoff_on());
    ed::CollapseGuard guard(2'000'000);
    bool collapsed = false;
    for (int k = 0; k < 40 && !collapsed; ++k) {
      ASSERT_FALSE(sim.run_until(150.0, 500'000)) << "no collapse before t = 150";
      collapsed = guard.collapsed(sim);
    }
    std::printf("  without TC: collapsed at t = %.9g (events per unit time %.3g, the run's average %.3g)\n",
                sim.time(), guard.rate(), guard.average_rate());
    EXPECT_TRUE(collapsed);
    EXPECT_LT(sim.time(), 150.0);
    EXPECT_EQ(sim.overlap_removals(), 0u);
  }
}

// No collapse: a dense box (η = 0.65, N = 2000) at e = 0.5 and 0.87 with τ_TC = 10^-4
// (≈ 2·10^-4 of the elastic mean free time 0.46, inside LM98's 10^-4 … 10^-2) cools by
// more than two decades, over hundreds of collisions per disk (at e = 0.87 the slower
// cooling leaves fewer, and the count grows only as log t), and reaches its target
// within the event budget.
TEST(TcModel, InelasticBoxesWithTheCutoffKeepAdvancing) {
  for (double e : {0.5, 0.87}) {
    ed::Config c = ed::test::periodic_box(2000, 0.65, 8);
    c.e = e;
    c.tau_tc = 1e-4;
    ed::Simulation sim(c);
    ed::CollapseGuard guard(2'000'000);
    const double target = e < 0.6 ? 400.0 : 1500.0;
    bool reached = false;
    std::uint64_t budgets = 0;
    for (; budgets < 120 && !reached; ++budgets) {  // ≤ 6·10^7 events
      reached = sim.run_until(target, 500'000);
      ASSERT_FALSE(guard.collapsed(sim)) << "e = " << e << ", t = " << sim.time();
    }
    const double per_disk = 2.0 * double(sim.stats().collisions) / sim.count();
    std::printf("  e = %.2f: t = %g after %.3g events, %.0f collisions per disk, kT %.3g -> %.3g, %.2g TC-elastic, "
                "%llu removal(s)\n",
                e, sim.time(), double(sim.stats().events), per_disk, c.kT, sim.state().kT(),
                double(sim.stats().tc_elastic) / double(sim.stats().collisions), (unsigned long long)sim.overlap_removals());
    EXPECT_TRUE(reached) << "e = " << e << ": stopped at t = " << sim.time();
    EXPECT_EQ(sim.time(), target);
    EXPECT_GT(per_disk, e < 0.6 ? 500.0 : 100.0);
    EXPECT_LT(sim.state().kT(), 0.01 * c.kT);
  }
}

// Haff's law for the homogeneous cooling of smooth disks. Per collision of equal masses
// the energy falls by (1 − r²)/4 · m v_n², and over colliding pairs (flux weighted by |v_n|,
// v_n Gaussian of variance 2T/m) <v_n²> = 4T/m: −(1 − r²) T per collision. With ω
// collisions per disk per unit time (N ω / 2 collisions) and E = N T in 2D,
// dT/dt = −(1 − r²) ω T / 2; ω ∝ √T gives T(t) = T0 / (1 + t/t0)², t0 = 4 / ((1 − r²) ω0).
// From an equilibrated elastic box (ω0 measured over its last 10 time units), the mean
// cooling rate over the first 0.05 and 0.1 t0 — t0_eff = t / (√(T0/T) − 1) — must match
// within 5 %; later times are printed (clustering makes the gas cool more slowly).
TEST(TcModel, HomogeneousCoolingFollowsHaffsLaw) {
  for (double r : {0.97, 0.87}) {
    ed::Config c = ed::test::periodic_box(16384, 0.65, 5);
    ed::Simulation sim(c);
    sim.run_until(10.0);  // melt the lattice, ≈ 20 collisions per disk
    sim.reset_measurements();
    sim.run_until(20.0);
    const double omega0 = sim.observables().collision_rate;
    const double T0 = sim.state().kT();
    const double t0 = 4.0 / ((1.0 - r * r) * omega0);
    sim.set_restitution(r);
    sim.set_time_cutoff(1e-4, 0.0);
    EXPECT_TRUE(sim.time_cutoff_on());
    const double ts = sim.time();
    const auto c0 = sim.stats().collisions;
    std::printf("  r = %.2f: omega0 = %.4f per disk per unit time, T0 = %.4g, t0 = %.4g\n", r, omega0, T0, t0);
    for (double f : {0.05, 0.1, 0.5, 1.0, 2.0, 5.0, 10.0}) {
      sim.run_until(ts + f * t0);
      const double T = sim.state().kT();
      const double haff = T0 / ((1.0 + f) * (1.0 + f));
      const double t0_eff = f * t0 / (std::sqrt(T0 / T) - 1.0);
      std::printf("    t = %5.2f t0: T/T0 = %.4f, Haff %.4f (measured/Haff %.4f); slope measured/predicted = %.4f; "
                  "%.1f collisions per disk, %.1e TC-elastic\n",
                  f, T / T0, haff / T0, T / haff, t0 / t0_eff, 2.0 * double(sim.stats().collisions - c0) / sim.count(),
                  double(sim.stats().tc_elastic) / double(sim.stats().collisions - c0));
      if (f <= 0.1) {
        EXPECT_NEAR(t0 / t0_eff, 1.0, 0.05) << "r = " << r << ", t = " << f << " t0";
      }
      if (f == 1.0) {
        EXPECT_NEAR(T / haff, 1.0, 0.08) << "r = " << r;
      }
    }
    EXPECT_EQ(sim.overlap_removals(), 0u);
  }
}

TEST(TcModel, RuntimeSettersCheckTheirValues) {
  ed::Config c = ed::test::periodic_box(200, 0.5, 1);
  ed::Simulation sim(c);
  EXPECT_THROW(sim.set_restitution(1.5), grainflow::Error);
  EXPECT_THROW(sim.set_restitution(-0.1), grainflow::Error);
  EXPECT_THROW(sim.set_restitution(std::nan("")), grainflow::Error);
  EXPECT_THROW(sim.set_time_cutoff(-1.0, 0.0), grainflow::Error);
  EXPECT_THROW(sim.set_time_cutoff(0.0, kInf), grainflow::Error);
  EXPECT_EQ(sim.restitution(), 1.0);
  sim.set_restitution(0.8);
  EXPECT_FALSE(sim.time_cutoff_on());  // no cutoff configured
  sim.set_time_cutoff(0.01, 0.001);
  EXPECT_TRUE(sim.time_cutoff_on());
  EXPECT_EQ(sim.restitution(), 0.8);
  EXPECT_EQ(sim.config().e, 1.0);  // the constructed value
  c.tau_tc = -1.0;
  EXPECT_THROW(ed::Simulation{c}, grainflow::Error);
}
