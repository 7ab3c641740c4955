// Contact numbers of a DEM packing: how many particles each sphere touches, and the mean
// coordination number Z of the bulk of a bed (seed 000 §4.1: a settled bed is judged by
// its packing; random frictional packings have Z ≈ 4–6, a stack of columns Z ≈ 2).
// UNITS: SI (m).
#pragma once
#include <cstddef>
#include <vector>

#include "engine/dem/simulation.hpp"

namespace grainflow::dem {

// Per particle, the particles it touches (centre distance below the sum of the current
// radii, the `contacts` of Stats counted from both ends). Wall contacts are not counted.
std::vector<int> contact_numbers(const Simulation& sim);

// The mean coordination number of the bed's bulk: particles whose centre lies at least
// `margin` from every wall (periodic axes have none) and at least `margin` below the free
// surface, taken as the 99th percentile of the centre heights (z) so that a few spheres
// still bouncing above the bed do not move it. Rattlers (Z = 0) are included, as in the
// usual definition of Z.
struct BulkCoordination {
  double mean = 0.0;          // mean contacts per bulk particle
  std::size_t particles = 0;  // particles in the bulk
  double z_lo = 0.0, z_hi = 0.0;  // the bulk's height range [m]
};
BulkCoordination bulk_coordination(const Simulation& sim, double margin);

}  // namespace grainflow::dem
