#include "engine/dem/field_sampler.hpp"

#include <vector>

namespace grainflow::dem {

void sample_fields(const Simulation& sim, core::BinAccumulator& acc) {
  const std::size_t n = sim.size();
  std::vector<Vec3> x(n), v(n);
  std::vector<double> r(n), m(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = sim.position(i);
    v[i] = sim.velocity(i);
    r[i] = sim.radius(i);
    m[i] = sim.mass(i);
  }
  const core::BinningOptions& o = acc.options();
  const int normal_axis = core::plane_normal(o.plane);
  const BoxConfig& b = sim.config().box;
  const double slab = (o.slab_lo && o.slab_hi) ? *o.slab_hi - *o.slab_lo : b.hi[normal_axis] - b.lo[normal_axis];
  acc.add(std::span<const Vec3>(x), std::span<const Vec3>(v), std::span<const double>(r), std::span<const double>(m), slab);
}

}  // namespace grainflow::dem
