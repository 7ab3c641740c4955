// What the machine's memory and cores allow the ED engine (seed 003 §2.4): the event loop
// is bound by cache misses at N ≳ 10^5, so its rate follows from these figures.
//  * dependent-load latency by working-set size (a random cyclic chase, one load per
//    64-byte line, on huge pages like the engine's arrays): where the last-level cache ends;
//  * independent misses: 16 chases interleaved over 256 MiB, ns per load — the cost of a
//    line when many are in flight, as in a neighbourhood scan;
//  * core to core: the round trip of a cache line between two threads on CPUs 0 and 1,
//    and a chase over 4 MiB written by the other core against one written by this core —
//    far above the local figure when the cores do not share a cache (then a second thread
//    that shares the event loop's working set costs more than it saves).
// Usage: bench_memory [--quick]. Medians of 3; run on a quiet machine.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <random>
#include <string>
#include <thread>
#include <vector>
#if defined(__linux__)
#include <pthread.h>
#include <sched.h>
#endif

#include "engine/ed/huge_pages.hpp"
#include "tests/bench/bench_args.hpp"

namespace {

using Clock = std::chrono::steady_clock;
struct alignas(64) Line {
  Line* next;
  char pad[64 - sizeof(Line*)];
};
using Buffer = grainflow::ed::HugeVector<Line>;

// Links the lines of b into one random cycle.
void link(Buffer& b, std::uint32_t seed) {
  std::vector<std::size_t> order(b.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::shuffle(order.begin() + 1, order.end(), std::mt19937_64(seed));
  for (std::size_t k = 0; k < order.size(); ++k) b[order[k]].next = &b[order[(k + 1) % order.size()]];
}

// ns per load of `chains` interleaved chases of `steps` loads each, starting spread over b.
double chase(const Buffer& b, int chains, std::size_t steps) {
  std::vector<const Line*> p(static_cast<std::size_t>(chains));
  for (int c = 0; c < chains; ++c) p[static_cast<std::size_t>(c)] = &b[b.size() * static_cast<std::size_t>(c) / static_cast<std::size_t>(chains)];
  const auto t0 = Clock::now();
  for (std::size_t s = 0; s < steps; ++s)
    for (auto& q : p) q = q->next;
  const double ns = std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
  std::uintptr_t sink = 0;
  for (auto* q : p) sink ^= reinterpret_cast<std::uintptr_t>(q);
  if (sink == 1) std::puts("");  // keeps the chase from being optimised away
  return ns / (static_cast<double>(steps) * chains);
}

double median3(double a, double b, double c) { return std::max(std::min(a, b), std::min(std::max(a, b), c)); }

bool pin(int cpu) {
#if defined(__linux__)
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  return pthread_setaffinity_np(pthread_self(), sizeof set, &set) == 0;
#else
  (void)cpu;
  return false;
#endif
}

// Round trip of one cache line between this thread (CPU 0) and a second one (CPU 1), ns.
double round_trip(int rounds, bool& pinned) {
  alignas(64) std::atomic<int> ping{0};
  alignas(64) std::atomic<int> pong{0};
  std::atomic<bool> ok{true};
  std::thread t([&] {
    ok = pin(1);
    for (int i = 1; i <= rounds; ++i) {
      while (ping.load(std::memory_order_acquire) != i) {}
      pong.store(i, std::memory_order_release);
    }
  });
  pinned = pin(0);
  const auto t0 = Clock::now();
  for (int i = 1; i <= rounds; ++i) {
    ping.store(i, std::memory_order_release);
    while (pong.load(std::memory_order_acquire) != i) {}
  }
  const double ns = std::chrono::duration<double, std::nano>(Clock::now() - t0).count() / rounds;
  t.join();
  pinned = pinned && ok;
  return ns;
}

// ns per load of a chase over b after the lines were last written by CPU `writer` (this
// thread chases on CPU 0).
double chase_after_write(Buffer& b, int writer, std::size_t steps) {
  auto write = [&] {
    pin(writer);
    link(b, 11);
  };
  if (writer == 0) write(); else std::thread(write).join();
  pin(0);
  return chase(b, 1, steps);
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  grainflow::bench::at_most("bench_memory", "bench_memory [--quick]", argc, argv, quick ? 1 : 0);
  const std::size_t steps = quick ? 200000 : 2000000;
  pin(0);
  std::printf("dependent-load latency (one chase)\n%12s %10s\n", "working set", "ns/load");
  for (double mib : {0.25, 2.0, 8.0, 12.0, 16.0, 32.0, 64.0, 256.0}) {
    Buffer b(static_cast<std::size_t>(mib * 1024 * 1024) / sizeof(Line));
    link(b, 7);
    chase(b, 1, b.size());  // warm up: fault in, fill the caches
    const double t = median3(chase(b, 1, steps), chase(b, 1, steps), chase(b, 1, steps));
    std::printf("%8.2f MiB %10.1f\n", mib, t);
    std::fflush(stdout);
  }
  {
    Buffer b(static_cast<std::size_t>(256) * 1024 * 1024 / sizeof(Line));
    link(b, 9);
    chase(b, 16, b.size() / 16);
    const double t = median3(chase(b, 16, steps / 4), chase(b, 16, steps / 4), chase(b, 16, steps / 4));
    std::printf("independent misses, 16 chases over 256 MiB: %.1f ns per load\n", t);
  }
  if (std::thread::hardware_concurrency() < 2) {
    std::printf("one CPU: no core-to-core figures\n");
    return 0;
  }
  bool pinned = false;
  const int rounds = quick ? 100000 : 1000000;
  const double rt = median3(round_trip(rounds, pinned), round_trip(rounds, pinned), round_trip(rounds, pinned));
  std::printf("core to core: round trip of a cache line %.0f ns (threads %s)\n", rt,
              pinned ? "on CPUs 0 and 1" : "not pinned");
  Buffer b(static_cast<std::size_t>(4) * 1024 * 1024 / sizeof(Line));
  const std::size_t n = b.size();
  const double own = median3(chase_after_write(b, 0, n), chase_after_write(b, 0, n), chase_after_write(b, 0, n));
  const double other = median3(chase_after_write(b, 1, n), chase_after_write(b, 1, n), chase_after_write(b, 1, n));
  std::printf("chase over 4 MiB written by this core: %.1f ns per load; by the other core: %.1f ns per load\n", own,
              other);
  return 0;
}
