// Binned fields of the DEM run over a chosen plane (seed 000 §2.2 DIAGNOS2 short/long
// term averages; fields as seed 003 §4.1 with i = 3): solid fraction, mean velocity,
// granular temperature, through core::BinAccumulator. SI units.
#pragma once
#include "engine/core/binning.hpp"
#include "engine/dem/simulation.hpp"

namespace grainflow::dem {

// Adds the current state (positions, full-step velocities, radii, masses) as one frame.
// Without a slab in the accumulator's options the slab is the box extent normal to the plane.
void sample_fields(const Simulation& sim, core::BinAccumulator& acc);

}  // namespace grainflow::dem
