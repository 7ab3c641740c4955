// The stochastic thermostat of seed 003 ch. 6 (engine/ed/thermostat.hpp): the velocities it
// assigns are Maxwell–Boltzmann at T_th (KS test per component), dual events conserve the
// pair's momentum at every event and the system's over a run, single/global events make
// the momentum walk (and a time-averaged local mean pins it), an elastic box started at
// kT = T_th/2 relaxes to T_th with relaxation time τ_th (single, global) or 2 τ_th (dual),
// events come at N/τ_th (N/(2 τ_th) pairs), a uniform stream and a shear profile survive
// the local mean (the shear does not survive the global one), and frozen disks beyond the
// filter are never touched while every boundary is in the box; single's local mean lifts the
// settled kT above T_th by about kT/n_b.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "engine/core/error.hpp"
#include "engine/core/rng.hpp"
#include "engine/ed/dense_stream.hpp"
#include "engine/ed/simulation.hpp"
#include "engine/ed/thermostat.hpp"
#include "tests/ed/ks_statistic.hpp"

namespace ed = grainflow::ed;
using grainflow::Vec2;

namespace {

constexpr ed::ThermostatKind kSingle = ed::ThermostatKind::single;
constexpr ed::ThermostatKind kDual = ed::ThermostatKind::dual;
constexpr ed::ThermostatKind kGlobal = ed::ThermostatKind::global;
const char* kind_name(ed::ThermostatKind k) { return ed::thermostat_kind_name(k).data(); }

ed::Config box(double l, double eta, double kT, std::uint64_t seed, Vec2 stream = Vec2::Zero()) {
  ed::Config c;
  c.lx = c.ly = l;
  c.area_fraction = eta;
  c.kT = kT;
  c.stream = stream;
  c.seed = seed;
  return c;
}

// Bins as close to `bin` as tile the box; the local field sampled 40 times per τ_v (the
// scene layer's rule).
ed::ThermostatConfig thermostat(ed::ThermostatKind kind, double T, double tau, double tau_v, double bin, double lx,
                                double ly, std::uint64_t seed) {
  ed::ThermostatConfig t;
  t.kind = kind;
  t.kT = T;
  t.tau = tau;
  t.tau_v = tau_v;
  t.sample_interval = tau_v / 40.0;
  t.grid.nx = std::max(1, int(std::lround(lx / bin)));
  t.grid.ny = std::max(1, int(std::lround(ly / bin)));
  t.grid.lo = {0.0, 0.0};
  t.grid.hi = {lx, ly};
  t.seed = seed;
  return t;
}

double normal_cdf(double x) { return 0.5 * std::erfc(-x / std::numbers::sqrt2); }

// Mean velocity of the disks (exact sum over the disks, not the books).
Vec2 mean_velocity(const ed::Simulation& sim) { return sim.momentum() / double(sim.state().mobile_count()); }

}  // namespace

// ---- 1. the assigned velocities -----------------------------------------------------------
TEST(EdThermostat, AssignedVelocitiesAreMaxwellBoltzmannAtTth) {
  const double T = 0.02;
  for (auto kind : {kSingle, kGlobal, kDual}) {
    SCOPED_TRACE(kind_name(kind));
    // Started at half T_th: what is assigned does not depend on the gas's temperature.
    ed::Simulation sim(box(30.0, 0.5, 0.01, 7));
    auto& th = sim.emplace_timer<ed::Thermostat>(thermostat(kind, T, 0.5, 5.0, 5.0, 30.0, 30.0, 11 + int(kind)), sim.state());
    const ed::SystemState& st = sim.state();
    std::vector<double> fx, fy;
    std::size_t local = 0;
    th.on_event = [&](const ed::ThermostatEvent& e) {
      // Read back from the disks, as set: v_i − mean (single, global), v_i − v_j (dual), in
      // units of its standard deviation sqrt(kT/m) or sqrt(kT/μ).
      Vec2 f = Vec2(st.disk[e.i].vx, st.disk[e.i].vy) - e.mean;
      double var = T / e.mi;
      if (e.j >= 0) {
        f = Vec2(st.disk[e.i].vx - st.disk[e.j].vx, st.disk[e.i].vy - st.disk[e.j].vy);
        var = T * (1.0 / e.mi + 1.0 / e.mj);
      }
      fx.push_back(f.x() / std::sqrt(var));
      fy.push_back(f.y() / std::sqrt(var));
      local += e.local;
    };
    while (fx.size() < 30000) sim.run_until(sim.time() + 1.0);
    const std::size_t n = fx.size();
    const double dx = grainflow::test::ks_statistic(fx, normal_cdf);
    const double dy = grainflow::test::ks_statistic(fy, normal_cdf);
    std::printf("%-6s: %zu events, KS vs N(0, kT_th/m): D_x = %.5f (p = %.3f), D_y = %.5f (p = %.3f), critical (0.001) "
                "%.5f; local means %zu\n",
                kind_name(kind), n, dx, grainflow::test::ks_p_value(n, dx), dy, grainflow::test::ks_p_value(n, dy),
                grainflow::test::ks_critical_001(n), local);
    EXPECT_LT(dx, grainflow::test::ks_critical_001(n));
    EXPECT_LT(dy, grainflow::test::ks_critical_001(n));
    // Single: after the first sample every bin of a dense box has a mean.
    if (kind == kSingle) EXPECT_GT(local, n * 99 / 100);
    else EXPECT_EQ(local, 0u);
  }
}

// ---- 2. dual events conserve momentum -----------------------------------------------------
TEST(EdThermostat, DualEventsConserveThePairsAndTheSystemsMomentum) {
  ed::Simulation sim(box(30.0, 0.6, 0.02, 5, {0.05, -0.02}));
  auto& th = sim.emplace_timer<ed::Thermostat>(thermostat(kDual, 0.03, 0.5, 5.0, 5.0, 30.0, 30.0, 3), sim.state());
  const ed::SystemState& st = sim.state();
  const double reach = 2.0 * std::numbers::sqrt2 * std::max(st.grid.width(), st.grid.height());
  double worst = 0.0, farthest = 0.0;
  std::uint64_t seen = 0;
  th.on_event = [&](const ed::ThermostatEvent& e) {
    ++seen;
    ASSERT_GE(e.j, 0);
    ASSERT_NE(e.i, e.j);
    const Vec2 before = e.mi * e.vi_before + e.mj * e.vj_before;
    const Vec2 after = e.mi * Vec2(st.disk[e.i].vx, st.disk[e.i].vy) + e.mj * Vec2(st.disk[e.j].vx, st.disk[e.j].vy);
    worst = std::max(worst, (after - before).norm());
    // The partner is local: within the 3 × 3 cells around disk i (minimum image).
    Vec2 d = st.position_now(e.i) - st.position_now(e.j);
    d.x() -= st.grid.lx() * std::round(d.x() / st.grid.lx());
    d.y() -= st.grid.ly() * std::round(d.y() / st.grid.ly());
    farthest = std::max(farthest, d.norm());
  };
  const Vec2 p0 = sim.momentum();
  const double e0 = sim.kinetic_energy();
  sim.run_until(60.0);
  const Vec2 p1 = sim.momentum();
  std::printf("dual: %llu pair events (%llu unpaired), max |Δp_pair| = %.3g, farthest partner %.2f σ (3x3 cells reach "
              "%.2f σ); system |P(60) − P(0)| = %.3g of |P(0)| = %.4f; kinetic energy %.2f → %.2f (T_th above kT)\n",
              (unsigned long long)th.events(), (unsigned long long)th.unpaired(), worst, farthest, reach,
              (p1 - p0).norm(), p0.norm(), e0, sim.kinetic_energy());
  EXPECT_EQ(seen, th.events());
  EXPECT_GT(th.events(), 20000u);
  EXPECT_EQ(th.unpaired(), 0u);  // η = 0.6: every disk has neighbours
  EXPECT_LT(worst, 1e-15);
  EXPECT_LE(farthest, reach + 1e-9);
  EXPECT_LT((p1 - p0).norm(), 1e-10 * sim.size());
  EXPECT_GT(sim.kinetic_energy(), e0 * 1.2);  // it did heat the gas
}

// ---- 3. the momentum walk of single (and global) events ----------------------------------
// Global (mean = the instantaneous system mean): ΔP = m (V − v_i) + m ξ per event, a
// martingale whose increments have E|ΔP|² = 2 m (kT + kT_th) (both components): the walk
// of §6 ("single thermostat events would cause the momentum in the system to perform a
// random walk"). Single (time-averaged local mean): the kicks pull P back towards its own
// average over τ_v, so the walk grows as in global only for t ≲ τ and then slows down.
TEST(EdThermostat, SingleEventsMakeTheMomentumRandomWalk) {
  const double T = 0.02, tau = 1.0, tau_v = 10.0;
  const int replicas = 12;
  // Interval ends: short ones first (t ≲ τ), then doubling.
  const double ends[] = {0.25, 0.5, 1.0, 2.5, 5.0, 10.0, 20.0, 40.0};
  constexpr std::size_t n_ends = std::size(ends);
  struct Walk {
    double msd[n_ends] = {}, events[n_ends] = {};  // Σ over replicas of |P(t) − P(0)|² and of events
    double increments = 0.0, increment_events = 0.0;  // |ΔP|² over the disjoint intervals
  };
  auto walk = [&](ed::ThermostatKind kind) {
    Walk w;
    for (int r = 0; r < replicas; ++r) {
      ed::Simulation sim(box(20.0, 0.5, T, 100 + r));
      auto& th = sim.emplace_timer<ed::Thermostat>(thermostat(kind, T, tau, tau_v, 5.0, 20.0, 20.0, 900 + r),
                                                   sim.state());
      const Vec2 p0 = sim.momentum();
      Vec2 p_prev = p0;
      std::uint64_t ev_prev = 0;
      for (std::size_t k = 0; k < n_ends; ++k) {
        sim.run_until(ends[k]);
        const Vec2 p = sim.momentum();
        w.msd[k] += (p - p0).squaredNorm();
        w.events[k] += double(th.events());
        w.increments += (p - p_prev).squaredNorm();
        w.increment_events += double(th.events() - ev_prev);
        p_prev = p;
        ev_prev = th.events();
      }
    }
    return w;
  };
  const double expected = 2.0 * (T + T);  // per event, m = 1, kT = kT_th
  const Walk g = walk(kGlobal), s = walk(kSingle), d = walk(kDual);
  std::printf("momentum walk, %d replicas of N = 254 (m = 1, kT = kT_th = %.2f, τ = %.1f, τ_v = %.0f), "
              "<|P(t) − P(0)|²> / <events> (random walk: 2 m (kT + kT_th) = %.3f):\n",
              replicas, T, tau, tau_v, expected);
  std::printf("     t   events   global   single   dual\n");
  for (std::size_t k = 0; k < n_ends; ++k)
    std::printf("  %5.2f  %7.0f  %.4f   %.4f   %.1e\n", ends[k], g.events[k] / replicas, g.msd[k] / g.events[k],
                s.msd[k] / s.events[k], d.msd[k] / d.events[k]);
  const double g_rate = g.increments / g.increment_events;
  std::printf("  global, disjoint increments: %.4f per event (%.0f events)\n", g_rate, g.increment_events);
  // Global: a random walk with the predicted step (variance ∝ number of events).
  EXPECT_NEAR(g_rate, expected, 0.25 * expected);
  EXPECT_NEAR(g.msd[n_ends - 1] / g.events[n_ends - 1], expected, 0.5 * expected);
  // Single: the same step while t ≪ τ, then pinned by the lagging local mean: at t = 40
  // far below global.
  EXPECT_NEAR(s.msd[0] / s.events[0], expected, 0.5 * expected);
  EXPECT_LT(s.msd[n_ends - 1] / s.events[n_ends - 1], 0.25 * g.msd[n_ends - 1] / g.events[n_ends - 1]);
  // Dual: no walk at all (round-off).
  EXPECT_LT(d.msd[n_ends - 1] / replicas, 1e-18);
}

// ---- 4. temperature control in an elastic box ---------------------------------------------
// Started at kT = 0.01 with T_th = 0.02: d(kT)/dt = (T_th − kT)/τ_r with τ_r = τ_th (single,
// global) or 2 τ_th (dual); kT ends at T_th (single: within its bin-mean excess, test 9). τ_r is measured from the area under the gap
// over [0, 2 τ_r,expected]: ∫ (T_th − kT)/(T_th − kT_0) dt = τ_r (1 − exp(−t_c/τ_r)).
TEST(EdThermostat, ElasticBoxRelaxesToTth) {
  const double T0 = 0.01, T = 0.02;
  for (auto kind : {kSingle, kGlobal, kDual}) {
    for (double tau : {1.0, 2.0, 4.0}) {
      SCOPED_TRACE(std::string(kind_name(kind)) + " tau " + std::to_string(tau));
      const double expected = kind == kDual ? 2.0 * tau : tau;
      ed::Simulation sim(box(60.0, 0.5, T0, 31));
      sim.emplace_timer<ed::Thermostat>(thermostat(kind, T, tau, 10.0, 6.0, 60.0, 60.0, 77), sim.state());
      const double gap0 = T - sim.state().kT();
      const double dt = expected / 50.0, t_c = 2.0 * expected;
      double area = 0.0, prev = 1.0;
      for (double t = dt; t <= t_c + 1e-9; t += dt) {
        sim.run_until(t);
        const double y = (T - sim.state().kT()) / gap0;
        area += 0.5 * (prev + y) * dt;
        prev = y;
      }
      // Solve τ (1 − e^{−t_c/τ}) = area (increasing in τ) by bisection.
      double lo = 0.01 * expected, hi = 100.0 * expected;
      for (int k = 0; k < 100; ++k) {
        const double mid = 0.5 * (lo + hi);
        (mid * (1.0 - std::exp(-t_c / mid)) < area ? lo : hi) = mid;
      }
      const double tau_r = 0.5 * (lo + hi);
      // Equilibrium: time average of kT over [8 τ_r, 16 τ_r].
      sim.run_until(8.0 * expected);
      sim.reset_measurements();
      sim.run_until(16.0 * expected);
      const double kT_end = sim.observables().kT;
      std::printf("%-6s tau_th = %.0f: relaxation time %.3f (expected %.0f, ratio %.3f); <kT> over [8, 16] τ_r = %.5f "
                  "(T_th %.2f, %+.2f %%), N = %d\n",
                  kind_name(kind), tau, tau_r, expected, tau_r / expected, kT_end, T, 100.0 * (kT_end / T - 1.0),
                  sim.count());
      EXPECT_NEAR(kT_end, T, 0.05 * T);
      // Dual relaxes a little slower than 2 τ_th: it never heats a pair's centre of mass,
      // which warms only through collisions, and long-wavelength flow (momentum conserved
      // locally) only through viscosity.
      EXPECT_NEAR(tau_r, expected, (kind == kDual ? 0.3 : 0.15) * expected);
    }
  }
}

// ---- 5. event rate ------------------------------------------------------------------------
TEST(EdThermostat, EventsComeAtNOverTau) {
  const double tau = 1.5, window = 60.0;
  for (auto kind : {kSingle, kGlobal, kDual}) {
    SCOPED_TRACE(kind_name(kind));
    ed::Simulation sim(box(40.0, 0.5, 0.02, 8));
    auto& th = sim.emplace_timer<ed::Thermostat>(thermostat(kind, 0.02, tau, 10.0, 5.0, 40.0, 40.0, 5 + int(kind)), sim.state());
    sim.run_until(5.0);
    const std::uint64_t e0 = th.events();
    sim.run_until(5.0 + window);
    const double n = double(th.events() - e0);
    const double expected = sim.count() * window / (kind == kDual ? 2.0 * tau : tau);
    std::printf("%-6s: %.0f events in %.0f (expected N T/%s = %.0f, %+.2f σ); %llu samples of the local field\n",
                kind_name(kind), n, window, kind == kDual ? "(2τ)" : "τ", expected, (n - expected) / std::sqrt(expected),
                (unsigned long long)th.samples());
    EXPECT_NEAR(n, expected, 5.0 * std::sqrt(expected));
    EXPECT_EQ(th.unpaired(), 0u);
    // Single samples every τ_v/40 from t = 0; the others take no samples.
    EXPECT_EQ(th.samples(), kind == kSingle ? std::uint64_t(std::floor((5.0 + window) / (10.0 / 40.0) + 1e-9)) : 0u);
  }
}

// ---- 6. the local mean keeps a stream, and a shear profile --------------------------------
TEST(EdThermostat, KeepsAUniformStream) {
  const Vec2 U(0.1, 0.0);
  const double tau = 1.0, t_end = 5.0;  // 5 τ: a mean reset to 0 would leave U e^{-5} ≈ 0.007 U
  for (auto kind : {kSingle, kGlobal, kDual}) {
    SCOPED_TRACE(kind_name(kind));
    ed::Simulation sim(box(80.0, 0.5, 0.02, 12, U));
    sim.emplace_timer<ed::Thermostat>(thermostat(kind, 0.02, tau, 10.0, 8.0, 80.0, 80.0, 13), sim.state());
    const Vec2 v0 = mean_velocity(sim);
    sim.run_until(t_end);
    const Vec2 v = mean_velocity(sim);
    std::printf("%-6s: mean velocity (%.5f, %.5f) → (%.5f, %.5f) after %.0f τ_th (N = %d)\n", kind_name(kind), v0.x(),
                v0.y(), v.x(), v.y(), t_end / tau, sim.count());
    // Random walk over 5 N events: σ(V) = sqrt(5 · 2 · 2 kT / N) ≈ 0.0045 per component.
    EXPECT_NEAR(v.x(), U.x(), 0.03);
    EXPECT_NEAR(v.y(), U.y(), 0.03);
  }
}

TEST(EdThermostat, LocalMeanKeepsAShearProfileGlobalDoesNot) {
  // v_x = A sin(2π y / L) on top of the Maxwell velocities. A local mean on 5 σ bins keeps
  // it (bin averaging costs sinc(π/12) ≈ 0.989 per kick: ≈ 11 % over 10 τ, viscosity
  // little more); the global mean (≈ 0) erases it at the kick rate, as e^{−t/τ}. Dual
  // pairs keep their centre-of-mass velocity and so the profile too.
  const double L = 60.0, A = 0.1, tau = 2.0, t_end = 20.0;
  const double k = 2.0 * std::numbers::pi / L;
  auto amplitude = [&](const ed::Simulation& sim) {
    double a = 0.0;
    for (int i = 0; i < sim.size(); ++i) {
      const Vec2 p = sim.state().position_now(i);
      a += sim.disks()[i].vx * std::sin(k * p.y());
    }
    return 2.0 * a / sim.count();
  };
  for (auto kind : {kSingle, kGlobal, kDual}) {
    SCOPED_TRACE(kind_name(kind));
    ed::Simulation sim(box(L, 0.5, 0.02, 21));
    ed::SystemState& st = sim.state();
    for (int i = 0; i < sim.size(); ++i)
      st.set_velocity(i, st.disk[i].vx + A * std::sin(k * st.disk[i].y), st.disk[i].vy);
    sim.emplace_timer<ed::Thermostat>(thermostat(kind, 0.02, tau, 10.0, 5.0, L, L, 22), sim.state());
    const double a0 = amplitude(sim);
    sim.run_until(t_end);
    const double a1 = amplitude(sim);
    std::printf("%-6s: shear amplitude %.4f → %.4f after %.0f τ_th (ratio %.3f; global mean would give e^-%.0f = %.1e)\n",
                kind_name(kind), a0, a1, t_end / tau, a1 / a0, t_end / tau, std::exp(-t_end / tau));
    if (kind == kGlobal) {
      EXPECT_LT(std::abs(a1 / a0), 0.2);
    } else {
      EXPECT_GT(a1 / a0, 0.6);
    }
  }
}

// ---- 7. boundaries: walls, obstacle, dispenser and filter ---------------------------------
TEST(EdThermostat, RunsBesideEveryBoundaryAndNeverTouchesFrozenDisks) {
  for (auto kind : {kSingle, kDual}) {
    SCOPED_TRACE(kind_name(kind));
    ed::Config c;
    c.lx = 60.0;
    c.ly = 20.0;
    c.area_fraction = 0.65;
    c.kT = 0.02;
    c.stream = {0.1, 0.0};
    c.periodic_x = false;
    c.open_x = true;
    c.periodic_y = false;  // elastic walls along y
    c.seed = 4;
    ed::Simulation sim(c);
    ed::ObstacleConfig oc;
    oc.centre = {28.0, 10.0};
    oc.radius = 4.0;
    oc.boundary = ed::ObstacleBoundary::thermal;
    oc.kT = c.kT;
    oc.seed = grainflow::core::substream_seed(c.seed, 1);
    sim.add_obstacle(oc);
    ed::DenseStreamConfig d;
    d.U = 0.1;
    d.kT = c.kT;
    d.area_fraction = 0.65;
    d.seed = grainflow::core::substream_seed(c.seed, 2);
    const ed::DenseStream dense = ed::add_dense_stream(sim, d);
    // Bins of D/10 = 0.8 σ would hold < 1 disk: take 2 σ (some bins lie inside the obstacle).
    auto& th = sim.emplace_timer<ed::Thermostat>(thermostat(kind, 0.025, 1.0, 10.0, 2.0, c.lx, c.ly, 9), sim.state());
    const ed::SystemState& st = sim.state();
    std::uint64_t frozen_touched = 0, fallback = 0;
    th.on_event = [&](const ed::ThermostatEvent& e) {
      frozen_touched += st.frozen(e.i) || (e.j >= 0 && st.frozen(e.j));
      fallback += kind == kSingle && !e.local;
    };
    sim.run_until(120.0);
    std::printf("%-6s beside walls, obstacle, dispenser and filter: %llu events (%llu unpaired, %llu global-mean "
                "fallbacks), %d frozen disks, %llu frozen ones touched, min gap %.2e\n",
                kind_name(kind), (unsigned long long)th.events(), (unsigned long long)th.unpaired(),
                (unsigned long long)fallback, st.frozen_count(), (unsigned long long)frozen_touched, sim.min_gap());
    EXPECT_GT(th.events(), 50000u);
    EXPECT_GT(st.frozen_count(), 0);
    EXPECT_GT(dense.filter->frozen(), 0u);
    EXPECT_EQ(frozen_touched, 0u);
    EXPECT_GE(sim.min_gap(), -1e-9);
    EXPECT_TRUE(std::isfinite(sim.kinetic_energy()));
  }
}

// ---- 8. invalid parameters ----------------------------------------------------------------
TEST(EdThermostat, InvalidParametersAreErrors) {
  ed::Simulation sim(box(20.0, 0.3, 0.02, 1));
  auto bad = [&](auto edit) {
    ed::ThermostatConfig t = thermostat(kSingle, 0.02, 1.0, 10.0, 5.0, 20.0, 20.0, 1);
    edit(t);
    EXPECT_THROW(ed::Thermostat(t, sim.state()), grainflow::Error);
  };
  bad([](ed::ThermostatConfig& t) { t.kT = 0.0; });
  bad([](ed::ThermostatConfig& t) { t.tau = -1.0; });
  bad([](ed::ThermostatConfig& t) { t.tau_v = 0.0; });
  bad([](ed::ThermostatConfig& t) { t.sample_interval = std::nan(""); });
  bad([](ed::ThermostatConfig& t) { t.grid.nx = 0; });
  try {
    ed::ThermostatConfig t = thermostat(kSingle, -0.5, 1.0, 10.0, 5.0, 20.0, 20.0, 1);
    ed::Thermostat th(t, sim.state());
    FAIL();
  } catch (const grainflow::Error& e) {
    EXPECT_NE(std::string(e.what()).find("T = -0.5 is invalid"), std::string::npos) << e.what();
  }
  // Dual and global need no bins.
  ed::ThermostatConfig t = thermostat(kDual, 0.02, 1.0, 10.0, 5.0, 20.0, 20.0, 1);
  t.grid.nx = 0;
  EXPECT_NO_THROW(ed::Thermostat(t, sim.state()));
}

// ---- 9. what the local mean adds ---------------------------------------------------------
// Single sets v = V_b + ξ: besides kT_th the disk gets m|V_b − V|²/2, the bin mean's own
// fluctuation (sampling noise and the slow hydrodynamic fluctuations of the bin's flow that
// the time average keeps), of order kT/n_b for n_b disks a bin. So an elastic box settles
// slightly above T_th, the more so the smaller the bins; global and dual settle at T_th.
TEST(EdThermostat, SingleSettlesAboveTthByTheBinMeansFluctuation) {
  auto excess = [](double bin) {
    ed::Simulation sim(box(60.0, 0.5, 0.02, 31));
    sim.emplace_timer<ed::Thermostat>(thermostat(kSingle, 0.02, 1.0, 10.0, bin, 60.0, 60.0, 78), sim.state());
    sim.run_until(20.0);
    sim.reset_measurements();
    sim.run_until(80.0);
    const double n_b = 0.5 * bin * bin / (std::numbers::pi / 4);
    const double x = sim.observables().kT / 0.02 - 1.0;
    std::printf("single, bins of %.0f σ (%.0f disks): <kT>/T_th − 1 = %+.4f (1/n_b = %.4f)\n", bin, n_b, x, 1.0 / n_b);
    return x;
  };
  const double small = excess(3.0), large = excess(20.0);
  EXPECT_GT(small, 0.02);
  EXPECT_GT(small, 2.0 * large);
  EXPECT_LT(std::abs(large), 0.01);
}
