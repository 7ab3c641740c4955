// Diffuse re-emission from a wall at temperature kT_b [TTKB98] (seed 003 §4.1: "re-emitting
// the collided particle with a random thermal velocity corresponding to the temperature of
// the boundary"), in the wall's frame: the flux-weighted normal speed away from the wall
// has the Rayleigh density (m v/kT) exp(−m v²/2kT), the tangential one is Gaussian with
// variance kT/m. The one sampler of both the thermal obstacle and the thermal walls.
#pragma once
#include <cmath>

#include "engine/core/rng.hpp"

namespace grainflow::ed {

struct WallFrameVelocity {
  double normal;      // ≥ 0, away from the wall
  double tangential;  // relative to the wall's own tangential velocity
};

// Two draws, in this order: the normal speed, then the tangential velocity.
inline WallFrameVelocity thermal_reemission(core::Rng& rng, double kT, double mass) {
  const double s2 = kT / mass;
  const double vn = std::sqrt(-2.0 * s2 * std::log(rng.uniform_pos()));
  const double vt = std::sqrt(s2) * rng.normal();
  return {vn, vt};
}

}  // namespace grainflow::ed
