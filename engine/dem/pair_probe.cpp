#include "engine/dem/pair_probe.hpp"

#include <cmath>

namespace grainflow::dem {

PairSample sample_pair(const Simulation& sim, std::size_t i, std::size_t j) {
  const auto& b = sim.config().box;
  Vec3 d = sim.position(j) - sim.position(i);
  for (int a = 0; a < 3; ++a)
    if (b.periodic[std::size_t(a)]) {
      const double L = b.hi[a] - b.lo[a];
      d[a] -= L * std::round(d[a] / L);
    }
  const double dist = d.norm();
  const Vec3 n = dist > 0 ? Vec3(d / dist) : Vec3(1, 0, 0);
  const double ri = sim.radius(i), rj = sim.radius(j);
  PairSample s;
  s.separation = dist - ri - rj;
  s.normal_force = sim.force(j).dot(n);
  ContactKinematics k{};
  k.delta = -s.separation;
  k.r_eff = ri * rj / (ri + rj);
  k.wall = false;
  s.cohesion_force = sim.contact_law().cohesion_force(type_pair(sim.group(i), sim.group(j)), k);
  s.contact_force = s.normal_force + s.cohesion_force;
  s.v_rel_n = (sim.velocity(j) - sim.velocity(i)).dot(n);
  return s;
}

}  // namespace grainflow::dem
