// How the threads of a DEM force pass wait for each other: per-chunk progress flags and a
// team barrier. A waiting thread spins (a neighbouring chunk's pair pass, a few µs, is
// usually about done; a futex sleep and wake-up costs 10–50 µs in a VM): 5 µs flat out,
// then yielding between checks up to 50 µs, then it sleeps. Yielding and sleeping leave
// the core to the thread being waited for when another process holds a core and two of
// ours share the other (N = 2,000, 2 threads against 1 with a busy loop beside them:
// ~0.75× with the yield, 0.3–0.5× without). Publishing wakes sleepers only when there
// are any: a futex wake-up per chunk otherwise costs ~1 % on one thread.
#pragma once
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <thread>

namespace grainflow::dem {

class ThreadSync {
public:
  // Per chunk: the number of the pass whose pair pass it has finished last, and the pass
  // in which a thread took the chunk or its rest (one cache line each: a thread polls its
  // neighbour's flag while another sets its own). Only equality with the current pass
  // counts, so the numbers may wrap.
  struct alignas(64) ChunkFlags {
    std::atomic<std::uint32_t> pass{0}, claim{0}, rest_claim{0};
  };

  void resize(std::size_t nchunks) {
    if (nchunks == size_) return;
    flags_ = std::make_unique<ChunkFlags[]>(nchunks);
    size_ = nchunks;
  }
  ChunkFlags& chunk(std::size_t c) { return flags_[c]; }

  // True for the one thread that takes `slot` in this pass.
  static bool take(std::atomic<std::uint32_t>& slot, std::uint32_t pass) {
    return slot.exchange(pass, std::memory_order_acq_rel) != pass;
  }

  void publish(std::atomic<std::uint32_t>& flag, std::uint32_t value) {
    // Sequentially consistent store then load, against the sleeper's increment then load:
    // either this thread sees the sleeper or the sleeper sees the value.
    flag.store(value, std::memory_order_seq_cst);
    if (sleepers_.load(std::memory_order_seq_cst) != 0) flag.notify_all();
  }

  void wait_for(const std::atomic<std::uint32_t>& flag, std::uint32_t value) {
    if (flag.load(std::memory_order_acquire) == value) return;
    const auto start = std::chrono::steady_clock::now();
    const auto yield_from = start + std::chrono::microseconds(5), give_up = start + std::chrono::microseconds(50);
    for (unsigned spins = 1;; ++spins) {
      if (flag.load(std::memory_order_acquire) == value) return;
#if defined(__x86_64__) || defined(__i386__)
      __builtin_ia32_pause();
#endif
      if (spins % 64 == 0) {
        const auto now = std::chrono::steady_clock::now();
        if (now > give_up) break;
        if (now > yield_from) std::this_thread::yield();
      }
    }
    for (;;) {
      sleepers_.fetch_add(1, std::memory_order_seq_cst);
      const std::uint32_t seen = flag.load(std::memory_order_seq_cst);
      if (seen != value) flag.wait(seen, std::memory_order_acquire);
      sleepers_.fetch_sub(1, std::memory_order_relaxed);
      if (flag.load(std::memory_order_acquire) == value) return;
    }
  }

  // All `team` threads of the calling parallel region meet here.
  void barrier(std::size_t team) {
    if (team <= 1) return;
    const std::uint32_t gen = generation_.load(std::memory_order_acquire);
    if (arrived_.fetch_add(1, std::memory_order_acq_rel) + 1 == team) {
      arrived_.store(0, std::memory_order_relaxed);  // nobody arrives before the release below
      publish(generation_, gen + 1);
    } else {
      wait_for(generation_, gen + 1);
    }
  }

private:
  std::unique_ptr<ChunkFlags[]> flags_;
  std::size_t size_ = 0;
  alignas(64) std::atomic<std::uint32_t> sleepers_{0};
  alignas(64) std::atomic<std::uint32_t> arrived_{0};
  alignas(64) std::atomic<std::uint32_t> generation_{0};
};

}  // namespace grainflow::dem
