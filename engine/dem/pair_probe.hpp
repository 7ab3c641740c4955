// The force–separation record of one pair of particles (seed 000 §5.4, Fig. 5.6–5.16):
// surface separation, the total force along the line of centres, the cohesion sub-model's
// attraction at that separation, and the normal relative velocity — what pair.csv holds.
#pragma once
#include <cstddef>

#include "engine/dem/simulation.hpp"

namespace grainflow::dem {

struct PairSample {
  // α = |x_j − x_i| − r_i − r_j (negative = overlap), minimum image across periodic axes [m].
  double separation = 0;
  // F_j·n with n = (x_j − x_i)/|x_j − x_i|, positive = repulsive: the pair force when
  // nothing else touches j [N].
  double normal_force = 0;
  // The contact law's cohesion at α (attractive > 0; 0 without cohesion) [N].
  double cohesion_force = 0;
  // normal_force + cohesion_force: the spring alone (Fig. 5.11) [N].
  double contact_force = 0;
  // (v_j − v_i)·n, positive = separating [m/s].
  double v_rel_n = 0;
};

PairSample sample_pair(const Simulation& sim, std::size_t i, std::size_t j);

}  // namespace grainflow::dem
