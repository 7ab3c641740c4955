#include "scenes/src/engines/memory_budget.hpp"

#include <cstdio>

#include <unistd.h>

namespace grainflow::scenes {

std::uint64_t physical_memory_bytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? std::uint64_t(pages) * std::uint64_t(page) : 0;
}

std::string memory_shortfall(double count, double bytes_per_item, const std::string& what) {
  const double need = count * bytes_per_item;
  const double have = double(physical_memory_bytes());
  if (have <= 0 || need <= 0.8 * have) return {};
  char buf[160];
  std::snprintf(buf, sizeof buf, "this scene needs ≈ %.3g GB for %.3g %s; this machine has %.3g GB", need / 1e9,
                count, what.c_str(), have / 1e9);
  return buf;
}

}  // namespace grainflow::scenes
