// Initial states for the ED engine: a triangular lattice with random vacancies that melts
// (random sequential addition jams near η ≈ 0.55 in 2D; seed 003 runs at η = 0.65), and
// Maxwell velocities at kT with zero total momentum plus a stream velocity U.
#pragma once
#include <cstdint>
#include <vector>

#include "engine/core/rng.hpp"
#include "engine/core/vec.hpp"

namespace grainflow::ed {

struct DiskInit {
  Vec2 r{0.0, 0.0};
  Vec2 v{0.0, 0.0};
  double omega = 0.0;
  double radius = 0.5;  // σ = 1
  double mass = 1.0;
  // The disk's persistent id (SystemState::tag); 0: numbered 1, 2, … in the given order.
  // Either every disk of a set has one (distinct, positive) or none does.
  std::int64_t tag = 0;
};

// n disks of the given diameter on a triangular lattice filling the box (centres kept
// at least a radius from non-periodic sides). Lattice sites are chosen by rng when there
// are more sites than disks; disks come out in row order (good memory locality).
// Throws grainflow::Error when n disks cannot be placed without overlap.
std::vector<DiskInit> triangular_lattice(int n, double diameter, double lx, double ly,
                                         bool periodic_x, bool periodic_y, core::Rng& rng);

// Maxwell–Boltzmann velocities: peculiar velocities drawn from N(0, kT/m) per component,
// shifted to zero total momentum and scaled so that Σ m|v|²/2 = N kT exactly (2D), then
// the stream velocity U added. With rotation = true also ω from N(0, kT/I), I = q m R².
void maxwell_velocities(std::vector<DiskInit>& disks, double kT, const Vec2& stream, bool rotation,
                        double q, core::Rng& rng);

}  // namespace grainflow::ed
