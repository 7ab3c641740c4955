// The contact law of a DEM run (seed 000 §2.4, ch. 5), composed at run time from a normal,
// a tangential and a cohesion sub-model (like LAMMPS GRANULAR's gran_sub_mod_*), each
// declaring its share of the per-contact history; the rows to choose from are the tables
// of contact_models.hpp.
#pragma once
#include <array>
#include <cstddef>
#include <memory>

#include "engine/dem/contact_kinematics.hpp"
#include "engine/dem/contact_params.hpp"
#include "engine/dem/neighbor_list.hpp"
#include "engine/dem/particle_state.hpp"

namespace grainflow::dem {

// Type of a contact partner: group 0, group 1, or a wall. Parameters are per type pair.
constexpr int kWallType = 2;
inline int type_pair(int a, int b) { return 3 * a + b; }

// Everything a force pass reads or writes; one pass over a range of particles.
struct ForcePass {
  Particles* p = nullptr;
  NeighborList* list = nullptr;
  const Box* box = nullptr;
  double* wall_hist = nullptr;          // 6 × history per particle
  std::uint8_t* wall_flags = nullptr;   // 6 per particle (NeighborList::k* bits)
  // Walls each particle may reach before the next rebuild: wall_slot[k] = 6 i + w for k in
  // [wall_first[i], wall_first[i+1]), ascending w (also the index of wall_flags/wall_hist).
  const std::uint32_t* wall_first = nullptr;
  const std::uint32_t* wall_slot = nullptr;
  double dt = 0.0;
  bool update = true;                   // false: evaluate only, history untouched
};

class ContactLaw {
public:
  virtual ~ContactLaw() = default;
  virtual int history_size() const = 0;
  // Largest reach of the cohesion sub-model beyond contact [m] (0 without cohesion).
  virtual double cohesion_range() const = 0;
  // Pair forces of the pairs owned by the particles of one force chunk [i0, i1): sets p->f
  // and p->t (Σ n × F_t) of the chunk's particles, scattering each pair to both members
  // when j lies in the chunk (particle by particle, ascending i, own pairs by ascending j);
  // pairs whose j lies beyond i1 also go to their list->cross_force slot for the caller
  // to gather (list->rfirst), who then multiplies the torque sums by R_i. Reads particles
  // i ≥ i0 only (pairs have j > i). virial non-null: the pairs' contact virial is added to
  // virial[6] (add_virial, in the order the forces are summed).
  virtual void pair_pass(const ForcePass& fp, std::size_t i0, std::size_t i1, double* virial) const = 0;
  // Wall forces of particles [i0, i1), added to p->f / p->t and to wall_sum[w][3];
  // virial non-null: the wall contacts' virial is added to virial[6], r = the centre
  // relative to its foot on the wall plane.
  virtual void wall_pass(const ForcePass& fp, std::size_t i0, std::size_t i1, double wall_sum[6][3],
                         double* virial) const = 0;
  // One contact, for tests and diagnostics. Returns false when out of range.
  virtual bool evaluate(int type_pair, const ContactKinematics& k, double* hist, bool update,
                        ContactForce& out) const = 0;
  // The attraction of the cohesion sub-model alone [N, attractive > 0] for a contact at
  // k.delta (−delta = surface gap); 0 without cohesion. For diagnostics (pair.csv).
  virtual double cohesion_force(int type_pair, const ContactKinematics& k) const = 0;
};

// One contact's share of the virial, r ⊗ F with r = x_i − x_partner (or x_i − the contact's
// foot on a wall) and F the force on i, in the order xx, yy, zz, xy, xz, yz; the
// off-diagonal terms symmetrised, (r_a F_b + r_b F_a)/2 (a tangential force makes r ⊗ F
// asymmetric; summed over all contacts the asymmetric part is the net contact torque,
// which vanishes in rotational equilibrium). Summing v in a fixed contact order is the
// caller's part.
inline void add_virial(double v[6], const double r[3], const double f[3]) {
  v[0] += r[0] * f[0];
  v[1] += r[1] * f[1];
  v[2] += r[2] * f[2];
  v[3] += 0.5 * (r[0] * f[1] + r[1] * f[0]);
  v[4] += 0.5 * (r[0] * f[2] + r[2] * f[0]);
  v[5] += 0.5 * (r[1] * f[2] + r[2] * f[1]);
}

// per_type[type_pair(a, b)] for a, b ∈ {0, 1} and b = kWallType; m_eff_pair[...] is the
// reduced mass used to turn a restitution into a damping rate (Hooke).
std::unique_ptr<ContactLaw> make_contact_law(const ContactModelSpec& spec,
                                             const std::array<ContactParams, 9>& per_type,
                                             const std::array<double, 9>& m_eff_pair);

}  // namespace grainflow::dem
