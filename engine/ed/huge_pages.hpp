// Backs the large per-disk arrays of the ED engine with transparent huge pages (seed 003
// §2.4 performance): the event loop touches them at random, and with 4 KiB pages nearly
// every access at N ≳ 10^5 also misses the TLB. Arrays of 2 MiB and more are allocated
// 2 MiB-aligned and advised (MADV_HUGEPAGE) before their first touch, so the kernel can
// fault them in as huge pages; advising memory that is already in place rarely gets them.
// A hint only: results never depend on it (without THP the arrays stay on small pages).
#pragma once
#include <cstddef>
#include <cstdlib>
#include <memory>
#include <new>
#include <vector>
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace grainflow::ed {

template <class T>
struct HugePageAllocator {
  using value_type = T;
  static constexpr std::size_t kHuge = std::size_t{1} << 21;

  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

  T* allocate(std::size_t n) {
    const std::size_t bytes = n * sizeof(T);
    if (bytes < kHuge) return std::allocator<T>{}.allocate(n);
    const std::size_t size = (bytes + kHuge - 1) & ~(kHuge - 1);
    void* p = std::aligned_alloc(kHuge, size);
    if (!p) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    madvise(p, size, MADV_HUGEPAGE);  // errors (THP off, old kernel) leave small pages
#endif
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t n) noexcept {
    if (n * sizeof(T) < kHuge) std::allocator<T>{}.deallocate(p, n);
    else std::free(p);
  }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const noexcept { return true; }
};

// A std::vector whose storage, once large, sits on huge pages.
template <class T>
using HugeVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace grainflow::ed
