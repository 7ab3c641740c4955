// The ED tests' and benchmark's reference state: a periodic square box of n disks at area
// fraction eta and kT = 0.02 (seed 003's equilibrium runs), from a melting lattice.
#pragma once
#include <cmath>
#include <cstdint>
#include <numbers>

#include "engine/ed/simulation.hpp"

namespace grainflow::ed::test {

inline Config periodic_box(int n, double eta, std::uint64_t seed) {
  Config c;
  c.n = n;
  c.lx = c.ly = std::sqrt(n * std::numbers::pi / 4.0 / eta);
  c.kT = 0.02;
  c.seed = seed;
  return c;
}

}  // namespace grainflow::ed::test
