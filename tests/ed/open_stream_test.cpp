// Low-density open stream boundaries (seed 003 §3.2): a channel periodic in y, open in x,
// with only the inlet (injection at n F+ L, removal of backward crossers) and the outlet
// (turn back with probability F−/F+, else remove). In the ideal-gas limit (η = 0.005) the
// channel must hold the stream's density, velocity, temperature and plane fluxes, and the
// W_x of the disks crossing a mid-channel plane must follow Eq. 3.27 at the stream's U, kT
// (seed Fig. 3.3) by the KS test of stream_flux_test. At the seed's η = 0.04 it must stay
// steady and within stated bounds of the stream (the missing collisional pressure at the
// open planes costs a few %). The outlet that deletes everything (the seed's high-Mach
// shortcut) must fail the density and crossing checks at a slow stream.
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "engine/core/error.hpp"
#include "engine/core/rng.hpp"
#include "engine/ed/cell_grid.hpp"
#include "engine/ed/low_density_stream.hpp"
#include "engine/ed/simulation.hpp"
#include "engine/io/archive.hpp"
#include "tests/ed/ks_statistic.hpp"
#include "tests/ed/plane_probe.hpp"

namespace ed = grainflow::ed;
using grainflow::test::ks_critical_001;
using grainflow::test::ks_statistic;

namespace {

struct Channel {
  double U, kT, eta;
  double lx = 80.0, ly = 100.0, x_in = 1.0, x_out = 79.0;
  double transient = 1000.0, duration = 20000.0;
  bool turn_back = true;
  std::uint64_t seed = 7;
};

struct Result {
  double n_target, n_mean, n_first, n_second, n_se;
  double u_mean, u_first, u_second, u_se, v_mean, kT_mean;
  double strip_dev;  // largest |strip density / mean density − 1| over 4 strips along x
  std::vector<double> crossings;
  std::uint64_t injected, skipped, blocked, removed_in, turned, removed_out;
  double min_gap;  // at the end: no overlap beyond round-off
};

Result run_channel(const Channel& ch) {
  const double n = 4.0 * ch.eta / std::numbers::pi;  // σ = 1
  const double area = (ch.x_out - ch.x_in) * ch.ly;
  // Start in the stream's state: random positions between the planes, Maxwell + U.
  grainflow::core::Rng rng(ch.seed);
  const int N = static_cast<int>(std::lround(n * area));
  std::vector<ed::DiskInit> disks;
  while (static_cast<int>(disks.size()) < N) {
    ed::DiskInit d;
    d.r = {rng.uniform(ch.x_in, ch.x_out), rng.uniform(0.0, ch.ly)};
    bool ok = true;
    for (const auto& o : disks) {
      const double dx = o.r.x() - d.r.x();
      double dy = std::abs(o.r.y() - d.r.y());
      dy = std::min(dy, ch.ly - dy);  // periodic in y
      if (dx * dx + dy * dy < 1.0) ok = false;
    }
    if (!ok) continue;
    d.v = {ch.U + std::sqrt(ch.kT) * rng.normal(), std::sqrt(ch.kT) * rng.normal()};
    disks.push_back(d);
  }
  ed::Config cfg;
  cfg.lx = ch.lx;
  cfg.ly = ch.ly;
  cfg.periodic_x = false;
  cfg.open_x = true;
  cfg.periodic_y = true;
  cfg.kT = ch.kT;
  cfg.seed = ch.seed;
  ed::Simulation sim(cfg, disks);

  ed::LowDensityStreamConfig sc;
  sc.U = ch.U;
  sc.kT = ch.kT;
  sc.number_density = n;
  sc.x_in = ch.x_in;
  sc.x_out = ch.x_out;
  sc.turn_back = ch.turn_back;
  sc.seed = ch.seed + 100;
  const ed::LowDensityStream st = ed::add_low_density_stream(sim, sc);
  auto* plane = static_cast<grainflow::test::PlaneProbe*>(sim.add_agent(std::make_unique<grainflow::test::PlaneProbe>(0.5 * (ch.x_in + ch.x_out))));

  sim.run_until(ch.transient);
  plane->recording = true;
  const int blocks = 20, per_block = 50;
  const double dt = ch.duration / (blocks * per_block);
  std::vector<double> bn(blocks, 0.0), bu(blocks, 0.0);
  double v_sum = 0.0, kT_sum = 0.0;
  double strip[4] = {0, 0, 0, 0};
  const ed::SystemState& s = sim.state();
  for (int b = 0; b < blocks; ++b)
    for (int k = 0; k < per_block; ++k) {
      sim.run_until(sim.time() + dt);
      double sx = 0.0, sy = 0.0, sxx = 0.0, syy = 0.0;
      int cnt = 0;
      for (int i = 0; i < s.size(); ++i) {
        if (!s.present(i)) continue;
        const ed::Disk& d = s.disk[i];
        const double x = s.position_now(i).x();
        ++cnt;
        sx += d.vx;
        sy += d.vy;
        sxx += (d.vx - ch.U) * (d.vx - ch.U);
        syy += d.vy * d.vy;
        strip[std::clamp(static_cast<int>(4.0 * (x - ch.x_in) / (ch.x_out - ch.x_in)), 0, 3)] += 1.0;
      }
      bn[b] += cnt / area / per_block;
      bu[b] += (cnt ? sx / cnt : 0.0) / per_block;
      v_sum += cnt ? sy / cnt : 0.0;
      // Eq. 4.9 with i = 2, peculiar velocities about this snapshot's own mean.
      if (cnt > 1) {
        const double mx = sx / cnt - ch.U, my = sy / cnt;
        kT_sum += (sxx - cnt * mx * mx + syy - cnt * my * my) / (2.0 * (cnt - 1));
      }
    }
  auto mean = [](const std::vector<double>& v, int lo, int hi) {
    double m = 0.0;
    for (int k = lo; k < hi; ++k) m += v[k];
    return m / (hi - lo);
  };
  auto se = [&](const std::vector<double>& v) {
    const double m = mean(v, 0, blocks);
    double q = 0.0;
    for (double x : v) q += (x - m) * (x - m);
    return std::sqrt(q / (blocks - 1) / blocks);
  };
  Result r;
  r.n_target = n;
  r.n_mean = mean(bn, 0, blocks);
  r.n_first = mean(bn, 0, blocks / 2);
  r.n_second = mean(bn, blocks / 2, blocks);
  r.n_se = se(bn);
  r.u_mean = mean(bu, 0, blocks);
  r.u_first = mean(bu, 0, blocks / 2);
  r.u_second = mean(bu, blocks / 2, blocks);
  r.u_se = se(bu);
  r.v_mean = v_sum / (blocks * per_block);
  r.kT_mean = kT_sum / (blocks * per_block);
  r.strip_dev = 0.0;
  const double strip_mean = 0.25 * (strip[0] + strip[1] + strip[2] + strip[3]);
  for (double c : strip) r.strip_dev = std::max(r.strip_dev, std::abs(c / strip_mean - 1.0));
  r.crossings = plane->wx;
  r.min_gap = sim.min_gap();
  r.injected = st.inlet->injected();
  r.skipped = st.inlet->skipped();
  r.blocked = st.inlet->blocked_tries();
  r.removed_in = st.inlet_plane->removed();
  r.turned = st.outlet->turned_back();
  r.removed_out = st.outlet->removed();
  std::printf("channel U=%g kT=%g eta=%g turn_back=%d: n/n0 = %.4f (halves %.4f, %.4f; block SE %.4f), "
              "<vx> = %.5f (halves %.5f, %.5f; SE %.5f), <vy> = %.5f, kT = %.5f, strip dev %.4f, "
              "crossings %zu, injected %llu (skipped %llu, blocked tries %llu), removed at inlet %llu, "
              "outlet turned %llu removed %llu\n",
              ch.U, ch.kT, ch.eta, ch.turn_back ? 1 : 0, r.n_mean / n, r.n_first / n, r.n_second / n, r.n_se / n,
              r.u_mean, r.u_first, r.u_second, r.u_se, r.v_mean, r.kT_mean, r.strip_dev, r.crossings.size(),
              (unsigned long long)r.injected, (unsigned long long)r.skipped, (unsigned long long)r.blocked,
              (unsigned long long)r.removed_in, (unsigned long long)r.turned, (unsigned long long)r.removed_out);
  return r;
}

// Kolmogorov–Smirnov distance of the mid-plane crossings from Eq. 3.27 at (U, kT).
double crossing_ks(const Result& r, double U, double kT) {
  const ed::StreamFlux f(U, kT);
  return ks_statistic(r.crossings, [&](double w) { return f.cdf_crossing(w); });
}

// Henderson's contact value of the hard-disk pair distribution, g(σ) = (1 − 7η/16)/(1 − η)².
double contact_value(double eta) { return (1.0 - 7.0 * eta / 16.0) / ((1.0 - eta) * (1.0 - eta)); }

// Why the level at η = 0.04 is a few % off the stream's: the seed's planes pass only
// kinetic momentum flux (no disk lies beyond them to collide with), while inside the
// channel the pressure has the collisional part 2ηg(σ)·nkT too. Balancing the x momentum
// flux n(kT + mU²) brought in against n'(kT(1 + 2ηg) + mU²) inside estimates the level
// (0.93 at U = 0.05; the measured 0.93–0.95 agrees; at high Mach mass-flux conservation
// dominates and the channel ends ~1 % denser and slower). Printed, not asserted.
double momentum_balance_density_ratio(double eta, double U, double kT) {
  return (kT + U * U) / (kT * (1.0 + 2.0 * eta * contact_value(eta)) + U * U);
}

}  // namespace

namespace {
ed::Config open_channel(double lx, double ly) {
  ed::Config c;
  c.lx = lx;
  c.ly = ly;
  c.periodic_x = false;
  c.open_x = true;
  c.periodic_y = true;
  return c;
}
}  // namespace

TEST(OpenStreamAgents, PlaneCellsAreTheColumnsHoldingThePlane) {
  const ed::CellGrid g(20.0, 10.0, false, true, 1.0);  // 20 × 10 cells of width 1
  std::vector<int> c;
  ed::plane_cells(g, 5.5, c);
  ASSERT_EQ(c.size(), 10u);
  for (int k : c) EXPECT_EQ(g.ix(k), 5);
  c.clear();
  ed::plane_cells(g, 5.0, c);  // on a column boundary: both columns
  EXPECT_EQ(c.size(), 20u);
}

TEST(OpenStreamAgents, OutletTurnsBackOrRemovesAtThePlane) {
  // U = 0: F−/F+ = 1, every disk reaching the outlet comes back with W_x < 0 (a thermal wall).
  {
    ed::Simulation sim(open_channel(20.0, 10.0), {ed::DiskInit{{10.0, 5.0}, {0.5, 0.0}}});
    auto flux = std::make_shared<const ed::StreamFlux>(0.0, 0.02);
    ed::StreamOutletConfig oc;
    oc.x = 19.0;
    auto* out = static_cast<ed::StreamOutlet*>(sim.add_agent(std::make_unique<ed::StreamOutlet>(oc, flux)));
    sim.run_until(17.9);  // reaches x = 19 at t = 18
    EXPECT_EQ(out->arrivals(), 0u);
    sim.run_until(18.1);
    EXPECT_EQ(out->turned_back(), 1u);
    EXPECT_EQ(sim.count(), 1);
    EXPECT_LT(sim.disks()[0].vx, 0.0);
  }
  // √c U = 25: F−/F+ ≈ 1e−277, the disk leaves.
  {
    ed::Simulation sim(open_channel(20.0, 10.0), {ed::DiskInit{{10.0, 5.0}, {0.5, 0.0}}});
    auto flux = std::make_shared<const ed::StreamFlux>(5.0, 0.02);
    ed::StreamOutletConfig oc;
    oc.x = 19.0;
    auto* out = static_cast<ed::StreamOutlet*>(sim.add_agent(std::make_unique<ed::StreamOutlet>(oc, flux)));
    sim.run_until(18.1);
    EXPECT_EQ(out->removed(), 1u);
    EXPECT_EQ(sim.count(), 0);
    EXPECT_EQ(sim.stats().removed, 1u);
  }
}

TEST(OpenStreamAgents, InletPlaneRemovesBackwardCrossers) {
  ed::Simulation sim(open_channel(20.0, 10.0), {ed::DiskInit{{5.0, 5.0}, {-0.5, 0.0}}, ed::DiskInit{{5.0, 2.0}, {0.5, 0.0}}});
  auto* plane = static_cast<ed::StreamInletPlane*>(sim.add_agent(std::make_unique<ed::StreamInletPlane>(1.0)));
  sim.run_until(7.9);  // reaches x = 1 at t = 8
  EXPECT_EQ(sim.count(), 2);
  sim.run_until(8.1);
  EXPECT_EQ(plane->removed(), 1u);
  EXPECT_EQ(sim.count(), 1);
}

TEST(OpenStreamAgents, InletInjectsAPoissonStreamAtRateNFL) {
  // An empty channel: arrivals over time T are Poisson with mean n F+ L T; every disk enters
  // on the plane with W_x > 0, and none overlaps another.
  ed::Simulation sim(open_channel(40.0, 100.0), {});
  ed::LowDensityStreamConfig sc;
  sc.U = 0.05;
  sc.kT = 0.02;
  sc.number_density = 0.05;
  sc.x_in = 1.0;
  sc.x_out = 39.0;
  sc.seed = 3;
  const ed::LowDensityStream st = ed::add_low_density_stream(sim, sc);
  const ed::StreamInlet& in = *st.inlet;
  const auto& flux = st.flux;
  const double T = 2000.0, mean = 0.05 * flux->flux_forward() * 100.0 * T;  // ≈ 849
  EXPECT_NEAR(in.rate(), 0.05 * flux->flux_forward() * 100.0, 1e-15);
  sim.run_until(T);
  EXPECT_NEAR(static_cast<double>(in.arrivals()), mean, 4.0 * std::sqrt(mean));
  EXPECT_EQ(in.injected() + in.skipped(), in.arrivals());
  EXPECT_EQ(in.skipped(), 0u);
  EXPECT_EQ(sim.stats().inserted, in.injected());
  EXPECT_EQ(static_cast<std::uint64_t>(sim.count()) + sim.stats().removed, in.injected());
  EXPECT_GE(sim.min_gap(), -1e-9);
  for (int i = 0; i < sim.state().size(); ++i)
    if (sim.state().present(i)) {
      const double x = sim.state().position_now(i).x();
      EXPECT_GE(x, 1.0 - 1e-9);
      EXPECT_LE(x, 39.0 + 1e-9);
    }
  EXPECT_THROW(ed::StreamInlet(ed::StreamInletConfig{1.0, 5.0, 5.0}, flux), grainflow::Error);
}

TEST(OpenStreamAgents, InstallRejectsPlanesOutsideTheBoxAndPeriodicX) {
  ed::Simulation sim(open_channel(20.0, 10.0), {});
  ed::LowDensityStreamConfig sc;
  sc.x_in = 5.0;
  sc.x_out = 3.0;
  EXPECT_THROW(ed::add_low_density_stream(sim, sc), grainflow::Error);
  sc.x_out = 25.0;
  EXPECT_THROW(ed::add_low_density_stream(sim, sc), grainflow::Error);
  ed::Config per = open_channel(20.0, 10.0);
  per.open_x = false;
  per.periodic_x = true;
  ed::Simulation sim2(per, {});
  sc.x_out = 15.0;
  EXPECT_THROW(ed::add_low_density_stream(sim2, sc), grainflow::Error);
}

TEST(OpenStream, IdealGasLimitKeepsTheStreamExactly) {
  // η = 0.005: the collisional pressure is 1 % of nkT, so the boundaries alone decide the
  // state, which must be the stream's: density, velocity, temperature, the fluxes through
  // both planes (Eq. 3.15/3.17, Poisson errors) and the crossing distribution Eq. 3.27.
  Channel ch{0.05, 0.02, 0.005};
  ch.lx = 40.0;  // short channel: the disk number decorrelates in a few hundred time units
  ch.x_out = 39.0;
  ch.ly = 2000.0;
  ch.duration = 40000.0;
  const Result r = run_channel(ch);
  // The 1 % collisional-pressure deficit is still there (0.991; a 2×10^5 run measures
  // 0.9905 with bench_open_stream): compare with it, within 3 %.
  EXPECT_NEAR(r.n_mean / r.n_target, momentum_balance_density_ratio(ch.eta, ch.U, ch.kT), 0.03);
  EXPECT_NEAR(r.n_second / r.n_target - r.n_first / r.n_target, 0.0, 0.03);
  EXPECT_NEAR(r.u_mean, ch.U, 0.002);
  EXPECT_NEAR(r.v_mean, 0.0, 0.002);
  EXPECT_NEAR(r.kT_mean / ch.kT, 1.0, 0.02);
  EXPECT_LT(r.strip_dev, 0.03);
  EXPECT_EQ(r.skipped, 0u);
  EXPECT_GE(r.min_gap, -1e-9);
  const ed::StreamFlux f(ch.U, ch.kT);
  const double T = ch.transient + ch.duration, L = ch.ly;
  const double in = r.n_target * f.flux_forward() * L * T, back = r.n_target * f.flux_backward() * L * T;
  EXPECT_NEAR(static_cast<double>(r.injected), in, 4.0 * std::sqrt(in));
  EXPECT_NEAR(static_cast<double>(r.removed_in), back, 0.03 * back);
  const double arrivals = static_cast<double>(r.turned + r.removed_out), p = f.turn_back_probability();
  EXPECT_NEAR(arrivals, in, 0.03 * in);
  EXPECT_NEAR(static_cast<double>(r.turned), p * arrivals, 4.0 * std::sqrt(arrivals * p * (1.0 - p)));
  // A KS test of no sample passes (its critical value is ∞): the plane must see the stream.
  EXPECT_GT(r.crossings.size(), 1000u);
  const double D = crossing_ks(r, ch.U, ch.kT), crit = ks_critical_001(r.crossings.size());
  std::printf("  mid-plane crossings vs Eq. 3.27 at the stream's U, kT: KS D = %.5f, critical (0.001) = %.5f\n", D, crit);
  EXPECT_LT(D, crit);
}

namespace {
// The seed's density η = 0.04: steady, uniform, within 10 % of the stream's density and
// velocity (see momentum_balance_density_ratio for the few-% offset), temperature within 5 %.
void check_seed_density_channel(const Channel& ch, const Result& r) {
  std::printf("  momentum-balance estimate of n'/n: %.4f\n", momentum_balance_density_ratio(ch.eta, ch.U, ch.kT));
  EXPECT_NEAR(r.n_mean / r.n_target, 1.0, 0.10);
  EXPECT_NEAR(r.n_second / r.n_target - r.n_first / r.n_target, 0.0, 0.05);  // no drift
  EXPECT_NEAR(r.u_mean / ch.U, 1.0, 0.10);
  EXPECT_NEAR(r.u_second / ch.U - r.u_first / ch.U, 0.0, 0.08);
  EXPECT_NEAR(r.v_mean / std::sqrt(ch.kT), 0.0, 0.03);
  EXPECT_NEAR(r.kT_mean / ch.kT, 1.0, 0.05);
  EXPECT_LT(r.strip_dev, 0.05);
  EXPECT_EQ(r.skipped, 0u);
  EXPECT_GE(r.min_gap, -1e-9);
  // Fig. 3.3: the crossing distribution has the form Eq. 3.27, here at the channel's own
  // U' and kT' (a few % off the stream's, see above; with estimated parameters the KS
  // critical value is conservative).
  EXPECT_GT(r.crossings.size(), 1000u);  // a KS test of no sample passes
  const double D = crossing_ks(r, r.u_mean, r.kT_mean), crit = ks_critical_001(r.crossings.size());
  std::printf("  mid-plane crossings vs Eq. 3.27 at U' = %.5f, kT' = %.5f: KS D = %.5f, critical (0.001) = %.5f "
              "(at the stream's U, kT: D = %.5f)\n",
              r.u_mean, r.kT_mean, D, crit, crossing_ks(r, ch.U, ch.kT));
  EXPECT_LT(D, crit);
}
}  // namespace

TEST(OpenStream, SeedDensityChannelU005) {
  Channel ch{0.05, 0.02, 0.04};
  ch.lx = 40.0;
  ch.x_out = 39.0;
  ch.ly = 200.0;
  check_seed_density_channel(ch, run_channel(ch));
}

TEST(OpenStream, SeedDensityChannelHighMach) {
  Channel ch{0.4, 0.02, 0.04};  // U / sqrt(kT) = 2.8
  ch.lx = 40.0;
  ch.x_out = 39.0;
  ch.ly = 200.0;
  ch.transient = 400.0;
  ch.duration = 8000.0;
  check_seed_density_channel(ch, run_channel(ch));
}

TEST(OpenStream, DeletingOutletStarvesASlowStream) {
  // The test that must fail: with every outlet arrival deleted the back flux F− is missing
  // and the channel empties towards the forward-moving share of the stream.
  Channel ch{0.05, 0.02, 0.04};
  ch.turn_back = false;
  ch.duration = 5000.0;
  const Result r = run_channel(ch);
  EXPECT_GT(std::abs(r.n_mean / r.n_target - 1.0), 0.2);
  EXPECT_GT(crossing_ks(r, ch.U, ch.kT), ks_critical_001(r.crossings.size()));
}
