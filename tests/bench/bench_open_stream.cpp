// Long-run steadiness of the low-density open stream boundaries (seed 003 §3.2): a channel
// open in x (inlet + outlet only), periodic in y, started in the stream's state; prints the
// number density n'/n, mean velocity U' and kT' per time block, their drift (least-squares
// slope over the run and last-half minus first-half), and events per second.
// Usage: bench_open_stream [--U 0.05] [--kT 0.02] [--eta 0.04] [--lx 40] [--ly 200]
//                          [--time 200000] [--transient 1000] [--blocks 20] [--seed 1]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/core/rng.hpp"
#include "engine/ed/low_density_stream.hpp"
#include "engine/ed/simulation.hpp"
#include "tests/bench/bench_args.hpp"

namespace ed = grainflow::ed;

namespace {
double slope(const std::vector<double>& t, const std::vector<double>& y) {
  const double n = static_cast<double>(t.size());
  double st = 0, sy = 0, stt = 0, sty = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    st += t[k];
    sy += y[k];
    stt += t[k] * t[k];
    sty += t[k] * y[k];
  }
  return (n * sty - st * sy) / (n * stt - st * st);
}
}  // namespace

int main(int argc, char** argv) try {
  double U = 0.05, kT = 0.02, eta = 0.04, lx = 40.0, ly = 200.0, T = 200000.0, transient = 1000.0;
  int blocks = 20;
  std::uint64_t seed = 1;
  constexpr const char* kUsage =
      "bench_open_stream [--U u] [--kT t] [--eta e] [--lx l] [--ly l] [--time T] [--transient t] [--blocks B] [--seed S]";
  for (int a = 1; a < argc; a += 2) {
    const std::string k = argv[a];
    // The option's value, a number in [lo, hi] (a whole one when `whole`).
    auto v = [&](double lo, double hi, bool whole = false) {
      return grainflow::bench::number_arg("bench_open_stream", kUsage, k, a + 1 < argc ? argv[a + 1] : nullptr, lo, hi,
                                          whole);
    };
    if (k == "--U") U = v(-1e3, 1e3);
    else if (k == "--kT") kT = v(1e-12, 1e6);
    else if (k == "--eta") eta = v(1e-6, 0.9);
    else if (k == "--lx") lx = v(3, 1e6);
    else if (k == "--ly") ly = v(3, 1e6);
    else if (k == "--time") T = v(1e-6, 1e12);
    else if (k == "--transient") transient = v(0, 1e12);
    else if (k == "--blocks") blocks = static_cast<int>(v(1, 1e6, true));
    else if (k == "--seed") seed = static_cast<std::uint64_t>(v(0, 9007199254740992.0, true));
    else grainflow::bench::usage_error("bench_open_stream", kUsage, "unknown option " + k);
  }
  const double n0 = 4.0 * eta / std::numbers::pi, x_in = 1.0, x_out = lx - 1.0;
  const double area = (x_out - x_in) * ly;
  // The stream's state between the planes: random sequential placement, Maxwell + U.
  grainflow::core::Rng rng(seed);
  const int N = static_cast<int>(std::lround(n0 * area));
  ed::Config cfg;
  cfg.lx = lx;
  cfg.ly = ly;
  cfg.periodic_x = false;
  cfg.open_x = true;
  cfg.periodic_y = true;
  cfg.kT = kT;
  cfg.seed = seed;
  std::vector<ed::DiskInit> disks;
  {
    ed::CellGrid g(lx, ly, false, true, 1.0);
    std::vector<std::vector<int>> cell(g.size());
    while (static_cast<int>(disks.size()) < N) {
      ed::DiskInit d;
      d.r = {rng.uniform(x_in, x_out), rng.uniform(0.0, ly)};
      const int c = g.cell_of_point(d.r.x(), d.r.y());
      bool ok = true;
      for (int ky = -1; ky <= 1 && ok; ++ky)
        for (int kx = -1; kx <= 1 && ok; ++kx) {
          const int cx = g.ix(c) + kx, cy = (g.iy(c) + ky + g.ny()) % g.ny();
          if (cx < 0 || cx >= g.nx()) continue;
          for (int j : cell[g.index(cx, cy)]) {
            const double dx = disks[j].r.x() - d.r.x();
            double dy = std::abs(disks[j].r.y() - d.r.y());
            dy = std::min(dy, ly - dy);
            if (dx * dx + dy * dy < 1.0) ok = false;
          }
        }
      if (!ok) continue;
      d.v = {U + std::sqrt(kT) * rng.normal(), std::sqrt(kT) * rng.normal()};
      cell[c].push_back(static_cast<int>(disks.size()));
      disks.push_back(d);
    }
  }
  ed::Simulation sim(cfg, disks);
  ed::LowDensityStreamConfig sc;
  sc.U = U;
  sc.kT = kT;
  sc.number_density = n0;
  sc.x_in = x_in;
  sc.x_out = x_out;
  sc.seed = seed + 100;
  const ed::LowDensityStream st = ed::add_low_density_stream(sim, sc);
  std::printf("channel %g x %g, planes at %g and %g, eta = %g (n = %.5f, N0 = %d), U = %g, kT = %g, "
              "F+ = %.5f, F- = %.5f, turn-back p = %.4f\n",
              lx, ly, x_in, x_out, eta, n0, N, U, kT, st.flux->flux_forward(), st.flux->flux_backward(),
              st.flux->turn_back_probability());
  const auto w0 = std::chrono::steady_clock::now();
  sim.run_until(transient);
  const ed::SystemState& s = sim.state();
  const int per_block = 100;
  const double dt = T / (blocks * per_block);
  std::vector<double> tb, nb, ub, kb;
  std::printf("%10s %10s %10s %10s\n", "t_mid", "n'/n", "U'", "kT'");
  for (int b = 0; b < blocks; ++b) {
    double n_acc = 0, u_acc = 0, k_acc = 0;
    for (int k = 0; k < per_block; ++k) {
      sim.run_until(sim.time() + dt);
      double sx = 0, sy = 0, sxx = 0, syy = 0;
      int c = 0;
      for (int i = 0; i < s.size(); ++i) {
        if (!s.present(i)) continue;
        const ed::Disk& d = s.disk[i];
        ++c;
        sx += d.vx;
        sy += d.vy;
        sxx += d.vx * d.vx;
        syy += d.vy * d.vy;
      }
      n_acc += c / area / n0;
      if (c > 1) {
        u_acc += sx / c;
        k_acc += (sxx - sx * sx / c + syy - sy * sy / c) / (2.0 * (c - 1));
      }
    }
    tb.push_back(sim.time() - 0.5 * dt * per_block);
    nb.push_back(n_acc / per_block);
    ub.push_back(u_acc / per_block);
    kb.push_back(k_acc / per_block);
    std::printf("%10.0f %10.4f %10.5f %10.5f\n", tb.back(), nb.back(), ub.back(), kb.back());
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  auto mean = [](const std::vector<double>& v, std::size_t lo, std::size_t hi) {
    double m = 0;
    for (std::size_t k = lo; k < hi; ++k) m += v[k];
    return m / static_cast<double>(hi - lo);
  };
  const std::size_t B = nb.size(), h = B / 2;
  std::printf("mean: n'/n = %.4f, U' = %.5f (U'/U = %.4f), kT' = %.5f (kT'/kT = %.4f)\n", mean(nb, 0, B),
              mean(ub, 0, B), mean(ub, 0, B) / U, mean(kb, 0, B), mean(kb, 0, B) / kT);
  std::printf("drift: last half - first half: n'/n %+.4f, U' %+.5f, kT' %+.5f; slope per 10^5 time units: "
              "n'/n %+.4f, U' %+.5f\n",
              mean(nb, h, B) - mean(nb, 0, h), mean(ub, h, B) - mean(ub, 0, h), mean(kb, h, B) - mean(kb, 0, h),
              1e5 * slope(tb, nb), 1e5 * slope(tb, ub));
  std::printf("inlet: %llu injected, %llu skipped, %llu blocked tries, %llu left backwards; outlet: %llu "
              "turned back, %llu removed; %.3g events in %.2f s (%.3g events/s)\n",
              (unsigned long long)st.inlet->injected(), (unsigned long long)st.inlet->skipped(),
              (unsigned long long)st.inlet->blocked_tries(), (unsigned long long)st.inlet_plane->removed(),
              (unsigned long long)st.outlet->turned_back(), (unsigned long long)st.outlet->removed(),
              static_cast<double>(s.stats.events), wall,
              static_cast<double>(s.stats.events) / wall);
  return 0;
} catch (const grainflow::Error& e) {
  std::fprintf(stderr, "error: %s\n", e.what());
  return 1;
}
