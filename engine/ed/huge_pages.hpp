// Backs the large per-disk arrays of the ED engine with transparent huge pages (seed 003
// §2.4 performance): the event loop touches them at random, and with 4 KiB pages nearly
// every access at N ≳ 10^5 also misses the TLB. A hint only: results never depend on it.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace grainflow::ed {

// Advises the kernel to use 2 MiB pages for the whole 2 MiB-aligned part of [p, p + bytes)
// (future faults) and collapses the pages already there. Errors are ignored (old kernels,
// THP disabled): the arrays then simply stay on small pages.
inline void advise_huge_pages(const void* p, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = std::uintptr_t{1} << 21;
  const auto a = reinterpret_cast<std::uintptr_t>(p);
  const std::uintptr_t lo = (a + kHuge - 1) & ~(kHuge - 1), hi = (a + bytes) & ~(kHuge - 1);
  if (hi <= lo) return;
  void* start = reinterpret_cast<void*>(lo);
  madvise(start, hi - lo, MADV_HUGEPAGE);
#if defined(MADV_COLLAPSE)
  madvise(start, hi - lo, MADV_COLLAPSE);
#else
  madvise(start, hi - lo, 25);  // MADV_COLLAPSE (Linux ≥ 6.1) where the headers predate it
#endif
#else
  (void)p;
  (void)bytes;
#endif
}

template <class T>
void advise_huge_pages(const std::vector<T>& v) {
  advise_huge_pages(v.data(), v.capacity() * sizeof(T));
}

}  // namespace grainflow::ed
