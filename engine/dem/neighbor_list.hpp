// The Verlet table of near-neighbour pairs with per-contact history (seed 000 §2.3),
// built by chain cells (cell linked list HEAD/LIST, 27-cell neighbourhoods with periodic
// wrap-around, §3.2–3.4) or by the N² reference search kept for validation (§4.1).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/dem/particle_state.hpp"

namespace grainflow::dem {

enum class NeighborMethod { ChainCells, AllPairs };

// Half list: the pairs of particle i are (i, j) with j > i, sorted by j, in
// [first[i], first[i+1]). Both search methods give the same table, entry for entry,
// so trajectories do not depend on the method.
struct NeighborList {
  static constexpr std::uint8_t kActive = 1;   // the pair exerts a force this step
  static constexpr std::uint8_t kHistory = 2;  // contact history may be non-zero

  int history_size = 0;
  std::vector<std::uint32_t> first;    // n + 1
  std::vector<std::uint32_t> partner;  // j per pair
  std::vector<std::uint32_t> owner;    // i per pair (from first), for flat loops over pairs
  std::vector<double> reach_sq;        // per pair ((R_i + range) + R_j)²: in range below it
  std::vector<std::uint8_t> shift;     // image shift code of j (Box::shift)
  std::vector<std::uint8_t> flags;
  std::vector<double> hist;            // history_size per pair
  // Pairs whose j lies in a later force chunk than i ("cross" pairs) hand j's share over
  // through a slot; slots are ordered by j, then ascending i, so that j's gather reads
  // them in sequence. Slot k of particle j is cross_force[6k, 6k+6): force on i (3),
  // n × F_t (3), kept zero while the pair is not active.
  std::vector<std::uint32_t> rfirst;       // n + 1: slots of particle j in [rfirst[j], rfirst[j+1])
  std::vector<std::uint32_t> cross_slot;   // slot per pair (0 for pairs within a chunk)
  std::vector<double> cross_force;         // 6 per slot
  // Per force chunk c: the first chunk with pairs into c (c if none). Pair passes read the
  // particles of their own and later chunks only, so chunk c may move its particles once
  // chunks chunk_dep[c] .. c − 1 have had theirs.
  std::vector<std::uint32_t> chunk_dep;
  std::vector<double> xref;            // positions at the last build (displacement check)
  std::uint64_t builds = 0;

  std::size_t pairs() const { return partner.size(); }
};

// Rebuilds `list` for the particles (wrapping positions into periodic axes first) with
// search distance R_i + R_j + extra_range + skin; history of surviving pairs is kept.
void build_neighbor_list(NeighborList& list, Particles& p, const Box& box, double skin,
                         double extra_range, NeighborMethod method);

// Fixed work unit of the force pass (particles [c·K, (c+1)·K) form chunk c). It depends on
// N only, never on the thread count, so the summation order (and the trajectory) is the
// same for any number of threads; about 16 chunks keep two threads balanced while most
// pairs stay inside one chunk, where the force is scattered directly. Small systems get
// chunks of 128: two threads that meet in the middle of the chunks then finish within
// ~1.5 µs of each other at N = 2,000 (chunks of 256: 1-thread runs ~4 % faster, 2-thread
// runs ~5 % slower).
std::size_t force_chunk_size(std::size_t n);

// The arrays derived from first/partner and the radii: owner, reach_sq for the force
// range R_i + R_j + `range` (cohesion), the slots of the cross pairs (rfirst,
// cross_slot), with all slots zeroed, and chunk_dep.
void index_pairs(NeighborList& list, const Particles& p, double range);

// Largest squared displacement since the last build (periodic axes already consistent,
// positions are wrapped only at a build).
double max_displacement_sq(const NeighborList& list, const Particles& p);

}  // namespace grainflow::dem
