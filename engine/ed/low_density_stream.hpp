// The matching pair of low-density open boundaries for a stream along +x (seed 003 §3.2):
// inlet (injector + backward-crossing plane) and outlet sharing one flux distribution,
// installed on a Simulation in one call — what the scene runner uses.
#pragma once
#include <cstdint>
#include <memory>

#include "engine/ed/stream_flux.hpp"
#include "engine/ed/stream_inlet.hpp"
#include "engine/ed/stream_outlet.hpp"

namespace grainflow::ed {

class Simulation;

struct LowDensityStreamConfig {
  double U = 0.05;                // stream velocity along +x (≥ 0)
  double kT = 0.02;               // stream temperature
  double number_density = 0.05;   // n, disks per unit area (η = n π σ²/4 for σ = 1)
  double radius = 0.5, mass = 1.0;
  double x_in = 1.0, x_out = 0.0; // planes; x_out ≤ 0 means box length − 1
  int max_tries = 20;
  bool turn_back = true;          // false: the outlet deletes every disk (high-Mach shortcut)
  std::uint64_t seed = 1;         // inlet uses seed, outlet a stream derived from it
};

struct LowDensityStream {
  std::shared_ptr<const StreamFlux> flux;
  StreamInlet* inlet = nullptr;         // owned by the simulation
  StreamInletPlane* inlet_plane = nullptr;
  StreamOutlet* outlet = nullptr;
};

// Registers the three agents. The x axis must not be periodic; best open (Config::open_x),
// else its elastic walls stay but never act, disks leaving at the planes first, which must
// then lie at least a radius inside the box. The inlet spans the whole height (periodic y)
// or [r, ly − r] (walls). Arrivals start at sim.time(). Disks already outside
// [x_in, x_out] are not removed (do it before: Simulation::remove_disks_unless).
// Throws grainflow::Error naming the offending value.
LowDensityStream add_low_density_stream(Simulation& sim, const LowDensityStreamConfig& cfg);

}  // namespace grainflow::ed
