// The ED tests' and benchmark's reference states: a periodic square box of n disks at area
// fraction eta and kT = 0.02 (seed 003's equilibrium runs), from a melting lattice; and the
// collapsing inelastic box of the TC model's tests; a disk placed by hand.
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

// Seed 003 ch. 5's collapsing box: a 50 × 50 periodic box at η = 0.65, kT = 0.02, e = 0.5,
// the TC cutoff starting at 0 and raised by 10^-4 at each overlap removal (the first comes
// at t ≈ 35 on one loop).
inline Config collapsing_box() {
  Config c;
  c.lx = c.ly = 50.0;
  c.area_fraction = 0.65;
  c.kT = 0.02;
  c.seed = 3;
  c.e = 0.5;
  c.tau_tc = 0.0;
  c.tau_tc_step = 1e-4;
  return c;
}

// A disk at (x, y) with velocity (vx, vy), the default radius and mass.
inline DiskInit disk_at(double x, double y, double vx, double vy) {
  DiskInit d;
  d.r = {x, y};
  d.v = {vx, vy};
  return d;
}

}  // namespace grainflow::ed::test
