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
  static constexpr std::uint8_t kActive = 1;   // pair force slot holds this step's force
  static constexpr std::uint8_t kHistory = 2;  // contact history may be non-zero

  int history_size = 0;
  std::vector<std::uint32_t> first;    // n + 1
  std::vector<std::uint32_t> partner;  // j per pair
  std::vector<std::uint8_t> shift;     // image shift code of j (Box::shift)
  std::vector<std::uint8_t> flags;
  std::vector<double> hist;            // history_size per pair
  std::vector<double> pair_force;      // 6 per pair: force on i (3), n × F_t (3); written
                                       // only for pairs whose j lies in a later force chunk
  std::vector<std::uint32_t> rfirst;   // n + 1: pairs where the particle is j and i lies in
  std::vector<std::uint32_t> rpair;    // an earlier force chunk, as pair indices, ascending i
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
// pairs stay inside one chunk, where the force is scattered directly.
std::size_t force_chunk_size(std::size_t n);

// Pairs in which each particle is the second member and the first member lies in an
// earlier force chunk (rfirst/rpair), ascending first member.
void build_reverse_index(NeighborList& list, std::size_t n);

// Largest squared displacement since the last build (periodic axes already consistent,
// positions are wrapped only at a build).
double max_displacement_sq(const NeighborList& list, const Particles& p);

}  // namespace grainflow::dem
