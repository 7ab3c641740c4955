// Running counters and accumulators of the ED engine (seed 003 §4.1 measurements):
// event/collision counts, time integral of kT, and the collision virial for the pressure.
#pragma once
#include <cstdint>

namespace grainflow::ed {

struct Stats {
  std::uint64_t events = 0;          // every calendar entry processed (incl. stale)
  std::uint64_t collisions = 0;      // disk–disk collisions performed
  std::uint64_t sliding = 0;         // of which in the Coulomb (sliding) branch
  std::uint64_t tc_elastic = 0;      // of which made elastic by the TC model (seed 003 ch. 5)
  std::uint64_t cell_crossings = 0;
  std::uint64_t stale = 0;           // events discarded because the partner changed
  std::uint64_t agent_events = 0;    // ParticleAgent actions (walls, obstacles, ...)
  std::uint64_t timer_events = 0;    // TimerAgent actions (sampler, thermostat, ...)
  std::uint64_t inserted = 0;        // disks that entered (open stream inlet, §3.2–3.3)
  std::uint64_t removed = 0;         // disks that left (outlet)
  // Disks removed because they overlapped numerically (TC model, seed 003 ch. 5; not in
  // `removed`): see SystemState::remove_overlapping.
  std::uint64_t removed_overlap = 0;

  // Measurement window: accumulators since reset at time t0.
  double t0 = 0.0;
  std::uint64_t collisions0 = 0;     // value of `collisions` at t0
  double kT_integral = 0.0;          // ∫ kT dt over [t0, now]
  double virial = 0.0;               // Σ_collisions r_ij · Δp_i (Δp_i: impulse on i)
  // The same as tensors (xx, xy, yy), for the pressure tensor: ∫ Σ m (v − V)_a (v − V)_b dt
  // (V the mass-averaged velocity, as kT), and Σ_collisions r_ij,a Δp_i,b, its xy part
  // symmetrised, (r_x Δp_y + r_y Δp_x)/2 (a rough collision's tangential impulse makes
  // the unsymmetrised sum unequal in xy and yx). Half their traces are kT_integral·N and
  // virial/2: the scalar pressure is half the tensor's trace.
  double kinetic_integral_xx = 0.0, kinetic_integral_xy = 0.0, kinetic_integral_yy = 0.0;
  double virial_xx = 0.0, virial_xy = 0.0, virial_yy = 0.0;
};

// A collision's virial, scalar and tensor (Stats::virial, virial_xx/xy/yy).
inline void add_virial(Stats& s, double rx, double ry, double jx, double jy) {
  s.virial += rx * jx + ry * jy;
  s.virial_xx += rx * jx;
  s.virial_xy += 0.5 * (rx * jy + ry * jx);
  s.virial_yy += ry * jy;
}

// Observables derived from Stats over the measurement window (see simulation.hpp).
struct Observables {
  double duration = 0.0;        // t − t0
  std::uint64_t collisions = 0;
  double kT = 0.0;              // time-averaged granular temperature (Eq. 4.9, i = 2)
  // Collision-virial pressure of hard disks in 2D (Alder & Wainwright 1960; Allen &
  // Tildesley 1987 §3.7 with d = 2): P = [N <kT> + (1/(2t)) Σ_coll r_ij · Δp_i] / A,
  // r_ij = r_i − r_j at contact, Δp_i the impulse on i; the sum is positive.
  double pressure = 0.0;
  // Pressure tensor over the same window, disks and area: P_ab = [<Σ m (v − V)_a (v − V)_b>
  // + (1/t) Σ_coll r_ij,a Δp_i,b] / A (Irving & Kirkwood 1950; Allen & Tildesley 1987
  // §2.4); (P_xx + P_yy)/2 = pressure.
  double pressure_xx = 0.0, pressure_xy = 0.0, pressure_yy = 0.0;
  double compressibility = 0.0; // Z = P A / (N kT)
  // Mean time between two collisions of the same disk: each collision involves two disks,
  // so τ = t N / (2 C) over a window of length t with C collisions.
  double mean_free_time = 0.0;
  double collision_rate = 0.0;  // collisions per unit time per disk = 2 C / (N t)
};

}  // namespace grainflow::ed
