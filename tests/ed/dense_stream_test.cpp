// The high-density open stream of seed 003 §3.3: dispenser piston + recharge (Fig. 3.9)
// at the inlet and the filter (Fig. 3.8) before the outlet. Pins the piston reflection,
// the dispensed flux, and the steadiness of a channel at η = 0.65, kT = 0.02 — and shows
// that deleting at the filter instead of freezing leaks (Fig. 3.7), so the check can fail.
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <random>
#include <cstdio>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "engine/core/error.hpp"
#include "engine/ed/dense_stream.hpp"
#include "engine/ed/simulation.hpp"

namespace ed = grainflow::ed;

namespace {

ed::Config channel(double lx, double ly, double U, std::uint64_t seed = 11) {
  ed::Config c;
  c.lx = lx;
  c.ly = ly;
  c.area_fraction = 0.65;
  c.kT = 0.02;
  c.stream = {U, 0.0};
  c.periodic_x = false;
  c.open_x = true;
  c.seed = seed;
  return c;
}

// Disks of the measurement region x ∈ [a, b] and their mean x-velocity.
struct Sample {
  double t, n, vx;
};
Sample measure(ed::Simulation& sim, double a, double b) {
  sim.synchronise();
  double n = 0, vx = 0;
  for (int i = 0; i < sim.size(); ++i) {
    if (!sim.present(i) || sim.state().frozen(i)) continue;
    const auto& d = sim.disks()[i];
    if (d.x < a || d.x > b) continue;
    n += 1;
    vx += d.vx;
  }
  return {sim.time(), n, n > 0 ? vx / n : 0.0};
}

// Least-squares slope of y(t).
double slope(const std::vector<Sample>& s, double Sample::*y) {
  double mt = 0, my = 0;
  for (const auto& p : s) mt += p.t, my += p.*y;
  mt /= double(s.size());
  my /= double(s.size());
  double num = 0, den = 0;
  for (const auto& p : s) num += (p.t - mt) * (p.*y - my), den += (p.t - mt) * (p.t - mt);
  return num / den;
}
double mean(const std::vector<Sample>& s, double Sample::*y) {
  double m = 0;
  for (const auto& p : s) m += p.*y;
  return m / double(s.size());
}

struct ChannelRun {
  std::vector<Sample> samples;  // after the transient
  double n_expected;            // η A_region / (π R²)
  std::uint64_t inserted, removed;
  double min_gap;
};

ChannelRun run_channel(bool delete_at_filter, double U, double t_transient, double t_end) {
  const double lx = 60, ly = 16, a = 12, b = 45;
  ed::Simulation sim(channel(lx, ly, U));
  ed::DenseStreamConfig dc;
  dc.U = U;
  dc.kT = 0.02;
  dc.area_fraction = 0.65;
  dc.filter_distance = 3.0;
  dc.delete_instead_of_freeze = delete_at_filter;
  dc.seed = 5;
  ed::add_dense_stream(sim, dc);
  ChannelRun out;
  out.n_expected = 0.65 * (b - a) * ly / (std::numbers::pi * 0.25);
  out.min_gap = ed::kNever;
  sim.run_until(t_transient);
  for (double t = t_transient; t <= t_end; t += 10.0) {
    sim.run_until(t);
    out.samples.push_back(measure(sim, a, b));
    out.min_gap = std::min(out.min_gap, sim.min_gap());
  }
  out.inserted = sim.stats().inserted;
  out.removed = sim.stats().removed;
  return out;
}

}  // namespace

TEST(Dispenser, PistonReflectsInItsFrameAndDispensesTheStreamFlux) {
  // A slow disk just ahead of the piston: it is hit when the piston catches up and leaves
  // at 2U − v (specular in the piston frame).
  const double U = 0.2;
  ed::Config c = channel(20, 8, U);
  std::vector<ed::DiskInit> d(1);
  d[0].r = {0.6, 4.0};
  d[0].v = {0.05, 0.01};
  ed::Simulation sim(c, d);
  ed::DenseStreamConfig dc;
  dc.U = U;
  dc.filter_distance = 2.0;
  auto stream = ed::add_dense_stream(sim, dc);
  // Contact when 0.6 + 0.05 t − 0.5 = 0.2 t, t = 2/3, before the recharge at 1/0.2 = 5.
  sim.run_until(1.0);
  EXPECT_EQ(stream.piston->hits(), 1u);
  EXPECT_NEAR(sim.disks()[0].vx, 2 * U - 0.05, 1e-15);
  EXPECT_EQ(sim.disks()[0].vy, 0.01);
  EXPECT_EQ(sim.stats().inserted, 0u);
  // Each recharge places η·σ·Ly/(π/4) disks on average (fractions carried over): 100 cycles.
  sim.run_until(100 * 5.0 + 1e-9);
  EXPECT_EQ(stream.piston->cycles(), 100u);
  const double per_cycle = 0.65 * 1.0 * 8 / (std::numbers::pi / 4);
  EXPECT_EQ(double(sim.stats().inserted), std::floor(100 * per_cycle + 1e-9));
  EXPECT_GE(sim.min_gap(), -1e-9);
}

TEST(Dispenser, ZeroStreamVelocityNeverRecharges) {
  ed::Simulation sim(channel(24, 10, 0.0));
  ed::DenseStreamConfig dc;
  dc.U = 0.0;
  auto stream = ed::add_dense_stream(sim, dc);
  const int n0 = sim.count();
  sim.run_until(200.0);
  EXPECT_EQ(stream.piston->cycles(), 0u);
  EXPECT_EQ(sim.stats().inserted, 0u);
  EXPECT_EQ(sim.stats().removed, 0u);
  EXPECT_EQ(sim.count(), n0);
  EXPECT_GT(stream.piston->hits(), 100u);  // a wall at x = 0
  EXPECT_GT(stream.filter->turned_back(), 100u);
  EXPECT_EQ(stream.filter->frozen(), 0u);  // U = 0: every disk is turned back (F− = F+)
  EXPECT_GE(sim.min_gap(), -1e-9);
}

TEST(Dispenser, RejectsImpossibleSettings) {
  ed::Config c = channel(20, 8, 0.1);
  c.open_x = false;
  ed::Simulation closed(c);
  EXPECT_THROW(ed::add_dense_stream(closed, ed::DenseStreamConfig{}), grainflow::Error);
  ed::Simulation sim(channel(20, 8, 0.1));
  ed::DenseStreamConfig dc;
  dc.filter_distance = 0.4;  // not more than a radius
  EXPECT_THROW(ed::add_dense_stream(sim, dc), grainflow::Error);
  dc.filter_distance = 3;
  dc.area_fraction = 0.8;  // a monolayer cannot hold it
  EXPECT_THROW(ed::add_dense_stream(sim, dc), grainflow::Error);
}

// Channel 60 × 16 (≈ 790 disks), η = 0.65, kT = 0.02, U = 0.05 (seed 003), periodic in y;
// measurement region x ∈ [12, 45]. After a transient of 300 (a quarter transit), over 1800
// time units (1.5 transits): the disk count stays within 2 % of the stream's η, drifts by
// less than 0.5 % of it per 100 time units, and the mean x-velocity stays within 0.01 of U
// with a drift below 0.004 per 100 time units.
TEST(DenseStream, DispenserAndFilterKeepTheStreamSteady) {
  const double U = 0.05;
  const ChannelRun r = run_channel(false, U, 300, 2100);
  const double n_mean = mean(r.samples, &Sample::n), vx_mean = mean(r.samples, &Sample::vx);
  const double n_drift = slope(r.samples, &Sample::n) * 100 / r.n_expected;
  const double v_drift = slope(r.samples, &Sample::vx) * 100;
  std::printf("dispenser+filter: <N> = %.1f (stream %.1f), drift %.2e per 100 τ (relative); <vx> = %.4f, drift %.2e "
              "per 100 τ; inserted %llu removed %llu\n",
              n_mean, r.n_expected, n_drift, vx_mean, v_drift, (unsigned long long)r.inserted,
              (unsigned long long)r.removed);
  EXPECT_NEAR(n_mean / r.n_expected, 1.0, 0.02);
  EXPECT_LT(std::abs(n_drift), 0.005);
  EXPECT_NEAR(vx_mean, U, 0.01);
  EXPECT_LT(std::abs(v_drift), 0.004);
  EXPECT_GE(r.min_gap, -1e-9);
  EXPECT_GT(r.removed, 0u);
}

TEST(DenseStream, DeletingAtTheFilterLeaks) {
  // The same channel with the low-density outlet rule (turn back with F−/F+, delete the
  // rest): seed 003 Fig. 3.7 — the density falls. The steadiness bounds above must fail.
  const double U = 0.05;
  const ChannelRun r = run_channel(true, U, 300, 2100);
  const double n_mean = mean(r.samples, &Sample::n);
  const double n_drift = slope(r.samples, &Sample::n) * 100 / r.n_expected;
  std::printf("delete at filter: <N> = %.1f (stream %.1f), drift %.2e per 100 τ (relative)\n", n_mean, r.n_expected,
              n_drift);
  EXPECT_TRUE(std::abs(n_mean / r.n_expected - 1.0) > 0.02 || std::abs(n_drift) > 0.005);
}

// An inelastic stream (e = 0.9 with the TC model, seed ch. 5) cools within a few τ. With the
// boundaries at the fixed stream temperature kT = 0.02, the dispenser keeps placing hot disks
// whose pressure accelerates the cold stream beyond U, and the filter freezes it back at U and
// turns back F−/F+ ≈ 17 % of it at kT = 0.02: a dense jam grows upstream from the outlet. With
// local_kT the boundaries take the cooled stream's temperature and the stream stays uniform.
struct CooledChannel {
  double n_in, n_out, vx_in, vx_out;  // density / η-stream density and <vx>, inlet and outlet thirds
  double kT_gas, kT_dispenser, kT_filter;
};
// Granular temperature of the mobile disks in x ∈ [a, b]: m|v − <v>|²/2 per disk (m = 1).
double region_kT(ed::Simulation& sim, double a, double b) {
  sim.synchronise();
  double n = 0, vx = 0, vy = 0, v2 = 0;
  for (int i = 0; i < sim.size(); ++i) {
    if (!sim.present(i) || sim.state().frozen(i)) continue;
    const auto& d = sim.disks()[i];
    if (d.x < a || d.x > b) continue;
    n += 1;
    vx += d.vx;
    vy += d.vy;
    v2 += d.vx * d.vx + d.vy * d.vy;
  }
  return 0.5 * (v2 / n - (vx * vx + vy * vy) / (n * n));
}

CooledChannel run_cooled(bool local_kT) {
  const double lx = 90, ly = 16, U = 0.1;
  ed::Config c = channel(lx, ly, U, 21);
  c.e = 0.9;
  c.tau_tc = 1e-4;
  c.tau_tc_step = 1e-5;
  ed::Simulation sim(c);
  ed::DenseStreamConfig dc;
  dc.U = U;
  dc.kT = 0.02;
  dc.area_fraction = 0.65;
  dc.local_kT = local_kT;
  dc.seed = 9;
  auto stream = ed::add_dense_stream(sim, dc);
  const double n_stream = 0.65 / (std::numbers::pi * 0.25);
  CooledChannel out{};
  double kT = 0, kT_dispenser = 0, kT_filter = 0;
  int samples = 0;
  for (double t = 500; t <= 900; t += 20) {
    sim.run_until(t);
    const Sample in = measure(sim, 5, 30), o = measure(sim, 57, 82);
    out.n_in += in.n / (25 * ly * n_stream);
    out.n_out += o.n / (25 * ly * n_stream);
    out.vx_in += in.vx;
    out.vx_out += o.vx;
    kT += region_kT(sim, 5, 82);
    // The boundaries' temperatures are running means over their last arrivals: taken at
    // the same times as the gas's, not once at the end, where a few arrivals decide.
    kT_dispenser += stream.piston->kT();
    kT_filter += stream.filter->kT();
    ++samples;
  }
  out.n_in /= samples;
  out.n_out /= samples;
  out.vx_in /= samples;
  out.vx_out /= samples;
  out.kT_gas = kT / samples;
  out.kT_dispenser = kT_dispenser / samples;
  out.kT_filter = kT_filter / samples;
  std::printf("cooled stream, local_kT = %d: n/n_stream inlet %.3f outlet %.3f, <vx> inlet %.4f outlet %.4f; kT gas "
              "%.2e, dispenser %.2e, filter %.2e; removed overlapping %llu\n",
              int(local_kT), out.n_in, out.n_out, out.vx_in, out.vx_out, out.kT_gas, out.kT_dispenser, out.kT_filter,
              (unsigned long long)sim.overlap_removals());
  return out;
}

TEST(DenseStream, CooledStreamJamsAtFixedTemperatureBoundaries) {
  const CooledChannel fixed = run_cooled(false);
  // The jam: the outlet third denser than the inlet third by more than 20 %.
  EXPECT_GT(fixed.n_out - fixed.n_in, 0.2);
  EXPECT_DOUBLE_EQ(fixed.kT_dispenser, 0.02);  // a mean of 0.02s, to round-off
  EXPECT_DOUBLE_EQ(fixed.kT_filter, 0.02);
}

TEST(DenseStream, LocalTemperatureBoundariesKeepACooledStreamUniform) {
  const CooledChannel local = run_cooled(true);
  // Measured (seed 21/9): n/n_stream 0.931 and 1.029, <vx> 0.106 and 0.105; fixed kT: 0.444
  // and 1.352, 0.225 and 0.089.
  EXPECT_NEAR(local.n_in, 1.0, 0.1);
  EXPECT_NEAR(local.n_out, 1.0, 0.1);
  EXPECT_NEAR(local.vx_in, 0.1, 0.01);
  EXPECT_NEAR(local.vx_out, 0.1, 0.01);
  // Both boundaries work at the cooled stream's temperature, 10^3 below the fixed 0.02: their
  // means within a factor 10 of the gas's. (Over 12 seed pairs from 21/9 on, the ratios
  // spread over 0.4–4.2 at the dispenser and 0.1–1.1 at the filter; read once, at the end,
  // over 0.1–3.5: a factor 2 held for the first seed pair only.)
  EXPECT_LT(local.kT_gas, 0.002);
  EXPECT_NEAR(std::log(local.kT_dispenser / local.kT_gas), 0.0, std::log(10.0));
  EXPECT_NEAR(std::log(local.kT_filter / local.kT_gas), 0.0, std::log(10.0));
}

TEST(Reorder, NextCollisionsAreTheSameUnderAnyNumbering) {
  // Renumbering brings every disk to the current time and predicts afresh; a run
  // renumbered at random and one renumbered in plain id order at the same moment must
  // then see the same collisions, pair by pair, bit for bit, until an exact tie between
  // two events (ordered by id) first tells them apart: the first 2,000 here.
  struct Hit {
    int i, j;
    double t;
    bool operator==(const Hit&) const = default;
  };
  auto run = [](bool shuffled) {
    ed::Config c;
    c.lx = c.ly = 40;
    c.area_fraction = 0.65;
    c.kT = 0.02;
    c.seed = 3;
    ed::Simulation sim(c);
    sim.run_until(50);
    const double energy = sim.kinetic_energy();
    std::vector<int> order;
    for (int i = 0; i < sim.size(); ++i)
      if (sim.present(i)) order.push_back(i);
    if (shuffled) std::shuffle(order.begin(), order.end(), std::mt19937(1));
    sim.reorder_disks(order);
    EXPECT_NEAR(sim.kinetic_energy(), energy, 1e-14 * energy);  // summed in the new order
    std::vector<Hit> hits;
    sim.set_collision_observer([&](const ed::CollisionRecord& r) {
      const int a = order[std::size_t(r.i)], b = order[std::size_t(r.j)];  // ids before the renumbering
      if (hits.size() < 2000) hits.push_back({std::min(a, b), std::max(a, b), r.t});
    });
    sim.run_until(60);
    EXPECT_NEAR(sim.kinetic_energy(), energy, 1e-12 * energy);
    EXPECT_GE(sim.min_gap(), -1e-9);
    return hits;
  };
  const std::vector<Hit> a = run(true), b = run(false);
  ASSERT_EQ(a.size(), 2000u);
  EXPECT_TRUE(a == b);
}

TEST(Reorder, CellOrderInAnOpenStream) {
  // An open stream whose slots were refilled by newcomers: after reorder_disks
  // (cell_order()) the ids run in cell order, and the stream runs on without overlaps
  // and without losing disks.
  const double U = 0.05;
  ed::Simulation sim(channel(60, 16, U));
  ed::DenseStreamConfig dc;
  dc.U = U;
  dc.kT = 0.02;
  dc.area_fraction = 0.65;
  dc.filter_distance = 3.0;
  dc.seed = 5;
  ed::add_dense_stream(sim, dc);
  sim.run_until(300);
  ASSERT_GT(sim.stats().inserted, 100u);  // the slots really were refilled
  sim.reorder_disks(sim.cell_order());
  const std::vector<int> after = sim.cell_order();
  for (std::size_t k = 0; k < after.size(); ++k) EXPECT_EQ(after[k], int(k));
  const int n = sim.count();
  sim.run_until(500);
  EXPECT_NEAR(double(sim.count()) / n, 1.0, 0.05);
  EXPECT_GE(sim.min_gap(), -1e-9);
}

TEST(Reorder, RejectsAnythingButAPermutationOfTheDisks) {
  ed::Simulation sim(channel(30, 10, 0.05));
  std::vector<int> order = sim.cell_order();
  ASSERT_GT(order.size(), 2u);
  std::vector<int> dup = order;
  dup[1] = dup[0];
  EXPECT_THROW(sim.reorder_disks(dup), grainflow::Error);
  std::vector<int> missing(order.begin() + 1, order.end());
  EXPECT_THROW(sim.reorder_disks(missing), grainflow::Error);
  std::vector<int> outside = order;
  outside[0] = sim.size();
  EXPECT_THROW(sim.reorder_disks(outside), grainflow::Error);
}

