// DEM throughput benchmark on the reference problem of /work/shared/bench/dem (README):
// Hooke + history (kn 100 N/m, kt 2/7 kn, γn 828.628 1/s (e = 0.9), γt = γn/2, μ 0.5),
// d = 1 mm, 2500 kg/m³, dt 5e-6 s, skin 0.2 d, simple cubic lattice at 1.02 d in a closed
// box 25 % taller than the lattice, gravity, v = 0.1 sin(c·id). Prints particle-steps/s
// (warm-up 1000 steps, timed 3000 like the LAMMPS input), then the neighbour-rebuild time
// against N with its fitted exponent. Threads: OMP_NUM_THREADS, or --threads 1,2 to run
// each size at each thread count back to back (speed-up under the same machine load). On
// a machine shared with other jobs set OMP_WAIT_POLICY=passive: spinning threads otherwise
// wait a scheduler time slice at every barrier (one per step, besides the short waits
// between neighbouring force chunks) and two threads run 20× slower than one. --digest
// prints a hash of the final state (bitwise comparisons).
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <cstring>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "engine/dem/simulation.hpp"
#include "tests/bench/bench_args.hpp"

using namespace grainflow;
using namespace grainflow::dem;

namespace {

Config bench_config(int nx, int ny, int nz) {
  const double d = 1e-3, a = 1.02 * d;
  Config c;
  c.box.lo = Vec3::Zero();
  c.box.hi = Vec3(nx * a, ny * a, 1.25 * nz * a);
  c.model = {NormalKind::Hooke, TangentialKind::History, CohesionKind::None};
  GroupConfig g;
  g.radius = 0.5 * d;
  g.density = 2500.0;
  g.contact.k1 = 100.0;
  g.contact.kt = 2.0 / 7.0 * 100.0;
  g.contact.e = 0.9;       // γn derived from e as LAMMPS users do (828.628 1/s)
  g.contact.gamma_n = -1;
  g.contact.gamma_t = -1;  // γn/2
  g.contact.mu = 0.5;
  c.groups = {g};
  c.dt = 5e-6;
  c.skin = 0.2 * d;
  const auto pos = simple_cubic_lattice(Vec3::Zero(), a, nx, ny, nz);
  for (std::size_t i = 0; i < pos.size(); ++i) {
    ParticleInit p;
    p.x = pos[i];
    const double id = static_cast<double>(i + 1);
    p.v = Vec3(0.1 * std::sin(12.9898 * id), 0.1 * std::sin(78.2330 * id), 0.1 * std::sin(37.7190 * id));
    c.particles.push_back(p);
  }
  return c;
}

// FNV-1a over the bits of positions, velocities and angular velocities.
std::uint64_t digest(const Particles& p) {
  std::uint64_t h = 1469598103934665603ull;
  for (const std::vector<double>* a : {&p.x, &p.v, &p.w})
    for (double d : *a) {
      std::uint64_t b;
      std::memcpy(&b, &d, sizeof b);
      for (int k = 0; k < 8; ++k) h = (h ^ ((b >> (8 * k)) & 0xff)) * 1099511628211ull;
    }
  return h;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  struct Grid {
    int nx, ny, nz;
  };
  // Arguments: grids "NXxNYxNZ" (default 10x10x20 25x25x32 40x40x40), "--large" adds
  // 50x50x80, "--no-fit" skips the rebuild-scaling fit, "--steps W,R" sets the warm-up
  // and timed steps (default 1000,3000), "--threads 1,2" the thread counts, "--digest".
  std::vector<Grid> grids;
  std::vector<int> threads;
  bool fit = true, large = false, show_digest = false;
  int nwarm = 1000, nrun = 3000;
  constexpr const char* kUsage = "bench_dem [NXxNYxNZ ...] [--large] [--no-fit] [--steps W,R] [--threads T1,T2] [--digest]";
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    const char* next = k + 1 < argc ? argv[k + 1] : nullptr;
    if (a == "--large") large = true;
    else if (a == "--no-fit") fit = false;
    else if (a == "--digest") show_digest = true;
    else if (a == "--steps") {
      const std::vector<int> s = bench::whole_list("bench_dem", kUsage, a, next, ',', 0, 1e9, 2);
      if (s[1] < 1) bench::usage_error("bench_dem", kUsage, "--steps: at least one timed step");
      nwarm = s[0];
      nrun = s[1];
      ++k;
    } else if (a == "--threads") {
      for (int t : bench::whole_list("bench_dem", kUsage, a, next, ',', 1, 1024)) threads.push_back(t);
      ++k;
    } else if (!a.empty() && a[0] == '-') {
      bench::usage_error("bench_dem", kUsage, "unknown option " + a);
    } else {
      const std::vector<int> n = bench::whole_list("bench_dem", kUsage, "grid", a.c_str(), 'x', 1, 1e4, 3);
      grids.push_back(Grid{n[0], n[1], n[2]});
    }
  }
  if (grids.empty()) grids = {{10, 10, 20}, {25, 25, 32}, {40, 40, 40}};
  if (large) grids.push_back({50, 50, 80});
  const char* th = std::getenv("OMP_NUM_THREADS");
  std::printf("# bench_dem: reference free-fall box, Hooke+history, OMP_NUM_THREADS=%s, %d+%d steps\n", th ? th : "(unset)",
              nwarm, nrun);
  // On a shared machine wall time includes waiting for a core: cpu_s is the process CPU
  // time of the loop (all threads), cpu% = cpu_s / loop_s as LAMMPS prints it.
  std::printf("%8s %4s %10s %14s %8s %18s %8s %8s %14s%s\n", "N", "thr", "loop_s", "pstep_per_s", "cpu%",
              "pstep_per_cpu_s", "builds", "coord", "ke_J", show_digest ? "             digest" : "");
  if (threads.empty()) threads.push_back(0);  // 0: as OMP_NUM_THREADS says
  std::vector<double> logn, logt;
  for (const Grid& g : grids) {
    for (int nt : threads) {
      int used = 1;
#ifdef _OPENMP
      if (nt > 0) omp_set_num_threads(nt);
      used = omp_get_max_threads();
#endif
      Simulation s(bench_config(g.nx, g.ny, g.nz));
      s.step(nwarm);
      const auto b0 = s.neighbors().builds;
      const auto t0 = std::chrono::steady_clock::now();
      const std::clock_t c0 = std::clock();
      s.step(nrun);
      const double dt = seconds_since(t0);
      const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
      const Stats st = s.stats();
      const double n = static_cast<double>(s.size());
      std::printf("%8zu %4d %10.3f %14.4g %8.1f %18.4g %8llu %8.3f %14.8g", s.size(), used, dt, n * nrun / dt,
                  100.0 * cpu / dt, n * nrun / cpu, static_cast<unsigned long long>(st.neighbor_builds - b0),
                  st.coordination, st.kinetic);
      if (show_digest) std::printf(" %016llx", static_cast<unsigned long long>(digest(s.particles())));
      std::printf("\n");
      std::fflush(stdout);
    }
  }
  if (!fit) return 0;
  // Neighbour-table rebuild cost against N (chain cells): process CPU time, best of 7
  // rebuilds per size (wall time on a shared machine measures the other users too).
  std::printf("# rebuild (chain cells): N, CPU seconds per rebuild\n");
  for (int k : {16, 25, 40, 60}) {
    Config c = bench_config(k, k, k);
    Particles p;
    Simulation s(c);  // validated configuration; rebuild on a copy of its particles
    p = s.particles();
    Box box;
    for (int a = 0; a < 3; ++a) {
      box.lo[a] = c.box.lo[a];
      box.hi[a] = c.box.hi[a];
    }
    box.finalize();
    NeighborList list;
    list.history_size = 3;
    double best = 1e30;
    for (int r = 0; r < 7; ++r) {
      const std::clock_t c0 = std::clock();
      build_neighbor_list(list, p, box, c.skin, 0.0, NeighborMethod::ChainCells);
      best = std::min(best, static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
    }
    std::printf("%8zu %12.4g\n", p.n, best);
    logn.push_back(std::log(static_cast<double>(p.n)));
    logt.push_back(std::log(best));
  }
  const double mn = [&] { double s = 0; for (double v : logn) s += v; return s / logn.size(); }();
  const double mt = [&] { double s = 0; for (double v : logt) s += v; return s / logt.size(); }();
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < logn.size(); ++i) {
    sxy += (logn[i] - mn) * (logt[i] - mt);
    sxx += (logn[i] - mn) * (logn[i] - mn);
  }
  std::printf("# rebuild time ∝ N^%.3f\n", sxy / sxx);
  return 0;
}
