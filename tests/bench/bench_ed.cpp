// Throughput of the ED hard-disk engine (seed 003 ch. 2): collisions per second on one
// core for the equilibrium periodic box at η = 0.65, kT = 0.02, for each calendar, after
// an equilibration period; reports the median of the timed windows and memory per disk.
// Usage: bench_ed [N ...] [--repeats R] [--per-disk C] [--calendar cell_heap|bucket] [--cell S]
//                 [--order lattice|shuffled|cells]
// --order: the disks' memory order for the timed windows — as the melted lattice left
// it (default), shuffled at random (what an open stream's refilled slots tend to), or
// renumbered in cell order (Simulation::reorder_disks(cell_order())).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/ed/simulation.hpp"

namespace ed = grainflow::ed;

int main(int argc, char** argv) try {
  std::vector<int> sizes;
  int repeats = 3;
  double per_disk = 20.0;  // timed collisions per disk in each window
  double cell = ed::Config{}.min_cell_size;  // minimum cell edge in σ (--cell 1.2: the seed's §2.2 optimum)
  std::string order = "lattice";
  std::vector<ed::CalendarKind> cals = {ed::CalendarKind::cell_heap, ed::CalendarKind::bucket};
  for (int a = 1; a < argc; ++a) {
    const std::string s = argv[a];
    if (s == "--repeats" && a + 1 < argc) repeats = std::atoi(argv[++a]);
    else if (s == "--per-disk" && a + 1 < argc) per_disk = std::atof(argv[++a]);
    else if (s == "--calendar" && a + 1 < argc) cals = {ed::calendar_from_name(argv[++a])};
    else if (s == "--cell" && a + 1 < argc) cell = std::atof(argv[++a]);
    else if (s == "--order" && a + 1 < argc) {
      order = argv[++a];
      if (order != "lattice" && order != "shuffled" && order != "cells") {
        std::fprintf(stderr, "bench_ed: --order %s: allowed lattice, shuffled, cells\n", order.c_str());
        return 2;
      }
    }
    else sizes.push_back(static_cast<int>(std::atof(s.c_str())));
  }
  if (sizes.empty()) sizes = {10000, 160000, 1000000};
  // Wall-clock rates suffer when the machine is shared; collisions per CPU-second of this
  // process (std::clock) is the one-core figure, reported beside it.
  std::printf("%-9s %-10s %14s %14s %14s %11s %9s %9s\n", "N", "calendar", "coll/s wall", "coll/s cpu",
              "events/s cpu", "stale/coll", "B/disk", "setup s");
  for (int n : sizes) {
    for (auto cal : cals) {
      const auto t0 = std::chrono::steady_clock::now();
      ed::Config c;
      const double l = std::sqrt(n * std::numbers::pi / 4.0 / 0.65);
      c.lx = c.ly = l;
      c.n = n;
      c.kT = 0.02;
      c.seed = 1;
      c.calendar = cal;
      c.min_cell_size = cell;
      ed::Simulation sim(c);
      // Equilibration: melt the lattice (≈ 10 collisions per disk).
      while (sim.stats().collisions < 10ull * n) sim.advance(100000);
      if (order == "shuffled") {
        std::vector<int> ids;
        for (int i = 0; i < sim.size(); ++i)
          if (sim.present(i)) ids.push_back(i);
        std::shuffle(ids.begin(), ids.end(), std::mt19937(7));
        sim.reorder_disks(ids);
      } else if (order == "cells") {
        sim.reorder_disks(sim.cell_order());
      }
      const double setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::vector<double> rates, crates, erates, stale;
      for (int r = 0; r < repeats; ++r) {
        const auto c0 = sim.stats().collisions, e0 = sim.stats().events, s0 = sim.stats().stale;
        const auto target = c0 + static_cast<std::uint64_t>(per_disk * n);
        const auto w0 = std::chrono::steady_clock::now();
        const std::clock_t k0 = std::clock();
        while (sim.stats().collisions < target) sim.advance(100000);
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
        const double cpu = double(std::clock() - k0) / CLOCKS_PER_SEC;
        rates.push_back((sim.stats().collisions - c0) / secs);
        crates.push_back((sim.stats().collisions - c0) / cpu);
        erates.push_back((sim.stats().events - e0) / cpu);
        stale.push_back(double(sim.stats().stale - s0) / double(sim.stats().collisions - c0));
      }
      auto median = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        return v[v.size() / 2];
      };
      std::printf("%-9d %-10s %14.4g %14.4g %14.4g %11.3f %9.1f %9.1f\n", n, sim.calendar(), median(rates),
                  median(crates), median(erates), median(stale), double(sim.memory_bytes()) / n, setup);
      std::fflush(stdout);
    }
  }
  return 0;
} catch (const grainflow::Error& e) {
  std::fprintf(stderr, "bench_ed: %s\n", e.what());
  return 1;
}
