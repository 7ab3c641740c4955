// Throughput of the ED hard-disk engine (seed 003 ch. 2): collisions per second on one
// core for the equilibrium periodic box at η = 0.65, kT = 0.02, for each calendar, after
// an equilibration period; reports the median of the timed windows and memory per disk.
// Usage: bench_ed [N ...] [--repeats R] [--per-disk C] [--calendar cell_heap|bucket] [--cell S]
//                 [--order lattice|shuffled|cells] [--checkpoint] [--threads 1|2] [--lanes 1|2]
// Memory: "hot B/disk" is what the event loop touches (Simulation::memory_parts), "B/disk"
// everything; each size's breakdown by array follows its row.
// --order: the disks' memory order for the timed windows — as the melted lattice left
// it (default), shuffled at random (what an open stream's refilled slots tend to), or
// renumbered in cell order (Simulation::reorder_disks(cell_order())).
// --threads 2: the two-lane loop (Config::lanes = threads = 2) on two threads; "coll/s cpu"
// then counts both threads' time. --lanes 2 --threads 1: the two lanes in their merged order
// on one thread, which is what the lanes cost without any waiting.
// --checkpoint: instead of the throughput, the size of a checkpoint of the equilibrated box
// (Simulation::save_state, default N = 160000) and the median wall time of save_state and
// of load_state (into a second simulation built the same way, construction not timed) over
// the repetitions; the restored state is checked to save the same bytes again.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <random>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/ed/simulation.hpp"
#include "tests/bench/bench_args.hpp"
#include "tests/ed/periodic_box.hpp"
#include "engine/io/archive.hpp"

namespace ed = grainflow::ed;
namespace bench = grainflow::bench;

namespace {

int g_threads = 1;  // --threads
int g_lanes = 0;    // --lanes (0: as many as threads)
int lanes() { return g_lanes > 0 ? g_lanes : g_threads; }

constexpr const char* kUsage =
    "bench_ed [N ...] [--repeats R] [--per-disk C] [--calendar cell_heap|bucket] [--cell S]\n"
    "                [--order lattice|shuffled|cells] [--checkpoint] [--threads 1|2] [--lanes 1|2]\n"
    "N: disk counts (default 10000 160000 1000000; 160000 with --checkpoint)";

ed::Config box(int n, ed::CalendarKind cal, double cell) {
  ed::Config c = ed::test::periodic_box(n, 0.65, 1);
  c.lanes = lanes();
  c.threads = g_threads;
  c.calendar = cal;
  c.min_cell_size = cell;
  return c;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

int bench_checkpoint(const std::vector<int>& sizes, const std::vector<ed::CalendarKind>& cals, int repeats,
                     double cell) {
  std::printf("%-9s %-10s %14s %9s %11s %11s %10s %10s\n", "N", "calendar", "bytes", "B/disk", "save s", "load s",
              "save MB/s", "load MB/s");
  for (int n : sizes) {
    for (auto cal : cals) {
      const ed::Config c = box(n, cal, cell);
      ed::Simulation sim(c);
      while (sim.stats().collisions < 10ull * n) sim.advance(100000);  // melt the lattice
      ed::Simulation target(c);  // built the same way; its construction is not timed
      std::vector<double> save_s, load_s;
      std::string bytes;
      for (int r = 0; r < repeats; ++r) {
        grainflow::io::ArchiveWriter w;
        const auto t0 = std::chrono::steady_clock::now();
        sim.save_state(w);
        save_s.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        bytes = w.take();
        grainflow::io::ArchiveReader in(bytes, "checkpoint");
        const auto t1 = std::chrono::steady_clock::now();
        target.load_state(in);
        load_s.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count());
      }
      grainflow::io::ArchiveWriter again;
      target.save_state(again);
      if (again.bytes() != bytes) {
        std::fprintf(stderr, "bench_ed: the restored state saved other bytes\n");
        return 1;
      }
      const double mb = double(bytes.size()) / 1e6;
      std::printf("%-9d %-10s %14zu %9.1f %11.4g %11.4g %10.0f %10.0f\n", n, sim.calendar(), bytes.size(),
                  double(bytes.size()) / n, median(save_s), median(load_s), mb / median(save_s), mb / median(load_s));
      std::fflush(stdout);
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) try {
  std::vector<int> sizes;
  int repeats = 3;
  double per_disk = 20.0;  // timed collisions per disk in each window
  double cell = ed::Config{}.min_cell_size;  // minimum cell edge in σ (--cell 1.2: the seed's §2.2 optimum)
  std::string order = "lattice";
  bool checkpoint = false;
  std::vector<ed::CalendarKind> cals = {ed::CalendarKind::cell_heap, ed::CalendarKind::bucket};
  for (int a = 1; a < argc; ++a) {
    const std::string s = argv[a];
    // The value after option s, as a number within [lo, hi].
    auto value = [&](double lo, double hi, bool whole = false) {
      const char* v = a + 1 < argc ? argv[++a] : nullptr;
      return bench::number_arg("bench_ed", kUsage, s, v, lo, hi, whole);
    };
    // The word after option s.
    auto word = [&]() -> std::string {
      if (a + 1 >= argc) bench::usage_error("bench_ed", kUsage, s + ": the value is missing");
      return argv[++a];
    };
    if (s == "--help" || s == "-h") {
      std::printf("usage: %s\n", kUsage);
      return 0;
    } else if (s == "--repeats") repeats = static_cast<int>(value(1, 1e6, true));
    else if (s == "--per-disk") per_disk = value(1e-3, 1e6);
    else if (s == "--calendar") {
      try {
        cals = {ed::calendar_from_name(word())};
      } catch (const grainflow::Error& e) {
        bench::usage_error("bench_ed", kUsage, e.what());
      }
    }
    else if (s == "--cell") cell = value(1e-3, 1e3);
    else if (s == "--checkpoint") checkpoint = true;
    else if (s == "--threads") g_threads = static_cast<int>(value(1, 2, true));
    else if (s == "--lanes") g_lanes = static_cast<int>(value(1, 2, true));
    else if (s == "--order") {
      order = word();
      if (order != "lattice" && order != "shuffled" && order != "cells")
        bench::usage_error("bench_ed", kUsage, "--order " + order + ": allowed lattice, shuffled, cells");
    } else if (!s.empty() && s[0] == '-') {
      bench::usage_error("bench_ed", kUsage, "unknown option " + s);
    } else {
      // Disk counts: whole numbers (1e6 and 1000000 alike), at most the cell map's 3-byte slots.
      sizes.push_back(static_cast<int>(bench::number_arg("bench_ed", kUsage, "N", s.c_str(), 1, 1 << 24, true)));
    }
  }
  if (checkpoint) {
    if (sizes.empty()) sizes = {160000};
    return bench_checkpoint(sizes, cals, std::max(repeats, 1), cell);
  }
  if (sizes.empty()) sizes = {10000, 160000, 1000000};
  // Wall-clock rates suffer when the machine is shared; collisions per CPU-second of this
  // process (std::clock) is the one-core figure, reported beside it.
  std::printf("%-9s %-10s %14s %14s %14s %11s %9s %9s %9s\n", "N", "calendar", "coll/s wall", "coll/s cpu",
              "events/s cpu", "stale/coll", "hot B/disk", "B/disk", "setup s");
  for (int n : sizes) {
    for (auto cal : cals) {
      const auto t0 = std::chrono::steady_clock::now();
      ed::Simulation sim(box(n, cal, cell));
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
        if (lanes() == 2) {
          // The two lanes run between stops in time: windows of the mean time that many
          // collisions took so far.
          const double per_time = double(sim.stats().collisions) / sim.time();
          while (sim.stats().collisions < target)
            sim.run_until(sim.time() + double(target - sim.stats().collisions) / per_time);
        } else {
          while (sim.stats().collisions < target) sim.advance(100000);
        }
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
        const double cpu = double(std::clock() - k0) / CLOCKS_PER_SEC;
        rates.push_back((sim.stats().collisions - c0) / secs);
        crates.push_back((sim.stats().collisions - c0) / cpu);
        erates.push_back((sim.stats().events - e0) / cpu);
        stale.push_back(double(sim.stats().stale - s0) / double(sim.stats().collisions - c0));
      }
      double hot = 0.0;
      std::string parts;
      for (const auto& p : sim.memory_parts()) {
        if (p.hot) hot += double(p.bytes);
        char b[96];
        std::snprintf(b, sizeof b, "%s%s %.1f%s", parts.empty() ? "" : ", ", p.name, double(p.bytes) / n,
                      p.hot ? "" : " (cold)");
        parts += b;
      }
      std::printf("%-9d %-10s %14.4g %14.4g %14.4g %11.3f %10.1f %9.1f %9.1f\n", n, sim.calendar(), median(rates),
                  median(crates), median(erates), median(stale), hot / n, double(sim.memory_bytes()) / n, setup);
      std::printf("#   B/disk: %s\n", parts.c_str());
      if (lanes() == 2)
        std::printf("#   runs between stops on two threads: %llu, done again in the merged order: %llu\n",
                    static_cast<unsigned long long>(sim.lane_runs().runs),
                    static_cast<unsigned long long>(sim.lane_runs().redone));
      std::fflush(stdout);
    }
  }
  return 0;
} catch (const grainflow::Error& e) {
  std::fprintf(stderr, "bench_ed: %s\n", e.what());
  return 1;
}
