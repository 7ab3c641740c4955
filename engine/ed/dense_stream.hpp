// The matching pair of high-density open boundaries for a stream along +x (seed 003 §3.3):
// the dispenser piston + recharge timer at the inlet x = 0 (Fig. 3.9) and the filter in
// front of the outlet x = Lx (Fig. 3.8), installed on a Simulation in one call.
#pragma once
#include "engine/ed/dispenser.hpp"
#include "engine/ed/stream_filter.hpp"

namespace grainflow::ed {

class Simulation;

struct DenseStreamConfig {
  double U = 0.05, kT = 0.02;     // the stream
  double area_fraction = 0.65;    // η of the stream (the dispensed monolayers)
  double filter_distance = 3.0;   // x_f = Lx − filter_distance, more than a radius
  PistonKind piston = PistonKind::elastic;
  bool delete_instead_of_freeze = false;  // the leaking low-density outlet (Fig. 3.7), for tests
  // The dispenser's new disks and the filter's back flux at the temperature of the disks
  // meeting the piston / arriving at the filter (a running mean over one monolayer's worth
  // of them) instead of kT: for streams that cool (inelastic disks, seed ch. 5).
  bool local_kT = false;
  std::uint64_t seed = 1;         // dispenser uses seed, the filter a stream derived from it
};

struct DenseStream {
  DispenserPiston* piston = nullptr;  // owned by the simulation
  DispenserRecharge* recharge = nullptr;
  StreamFilter* filter = nullptr;
};

// Registers the three agents on a simulation whose x axis is open (Config::open_x) and
// whose disks all have the same radius and mass (taken from disk 0). Disks already beyond
// the filter plane are frozen at (U, 0) so the outlet starts closed. Throws
// grainflow::Error naming the offending value.
DenseStream add_dense_stream(Simulation& sim, const DenseStreamConfig& cfg);

}  // namespace grainflow::ed
