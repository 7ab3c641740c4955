#include "engine/dem/packing.hpp"

#include <algorithm>
#include <cmath>

namespace grainflow::dem {

std::vector<int> contact_numbers(const Simulation& sim) {
  const std::size_t n = sim.size();
  const NeighborList& list = sim.neighbors();
  std::vector<int> z(n, 0);
  // Every touching pair is in the Verlet table (its search distance exceeds the sum of
  // the radii), with the periodic image it touches through.
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint32_t q = list.first[i]; q < list.first[i + 1]; ++q) {
      const std::uint32_t j = list.partner[q];
      const double rs = sim.radius(i) + sim.radius(j);
      if (sim.centre_distance_sq(i, q) < rs * rs) ++z[i], ++z[j];
    }
  return z;
}

BulkCoordination bulk_coordination(const Simulation& sim, double margin) {
  BulkCoordination out;
  const std::size_t n = sim.size();
  if (n == 0) return out;
  std::vector<double> heights(n);
  for (std::size_t i = 0; i < n; ++i) heights[i] = sim.position(i).z();
  const std::size_t k = std::min(n - 1, std::size_t(std::floor(0.99 * double(n - 1))));
  std::nth_element(heights.begin(), heights.begin() + std::ptrdiff_t(k), heights.end());
  const BoxConfig& box = sim.config().box;
  out.z_lo = box.periodic[2] ? box.lo.z() : box.lo.z() + margin;
  out.z_hi = heights[k] - margin;
  const std::vector<int> z = contact_numbers(sim);
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 x = sim.position(i);
    bool inside = x.z() >= out.z_lo && x.z() <= out.z_hi;
    for (int a = 0; a < 2 && inside; ++a)
      if (!box.periodic[std::size_t(a)]) inside = x[a] - box.lo[a] >= margin && box.hi[a] - x[a] >= margin;
    if (!inside) continue;
    sum += z[i];
    ++out.particles;
  }
  out.mean = out.particles ? sum / double(out.particles) : 0.0;
  return out;
}

}  // namespace grainflow::dem
