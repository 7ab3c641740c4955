// Planar Couette flow → kinematic viscosity (seed 003 §4.2: "simple planar 2D Couette flow
// simulations ... 128 × 128, kT = 0.02, velocities of the moving boundary 0.025, 0.05 and
// 0.1 ... ν ≈ 0.65"). Two walls in y move along x ([boundary.walls] U = [U_low, U_high]),
// the box is periodic in x. In the steady state the shear stress σ_xy is uniform across
// the channel and equals the x force per unit length the top wall exerts on the gas (and
// minus that of the bottom wall); the velocity profile u_x(y) is linear in the bulk, away
// from the walls' slip (Knudsen) layers. Newton's law σ_xy = ρ ν du_x/dy gives ν.
//
// analyse_couette() is the measurement: time blocks (each an exposure of the field
// sampler and the stats rows over the same interval) → the stress, the bulk gradient
// (least-squares slope of each block's profile over the bulk bins), the bulk mass density,
// and ν = σ̄ / (ρ̄ ḡ) with its standard error from the block-to-block scatter (delta
// method with the covariances of the three block means; blocks much longer than the
// stress correlation time are independent). The `[study] kind = "couette"` of a scene
// (couette.cpp) gathers the blocks from its run and writes the result.
#pragma once
#include <cstddef>
#include <vector>

namespace grainflow::scenes {

struct CouetteBlock {
  std::vector<double> ux;       // mean x velocity of each y bin (NaN: empty bin)
  std::vector<double> density;  // number density of each y bin, 1/σ²
  double fx_low = 0.0;          // x force per unit length the wall at y = 0 exerts on the gas
  double fx_high = 0.0;         // the same for the wall at y = Ly
  double kT = 0.0;              // the gas's mean kT over the block (reported, not used)
};

struct CouetteInput {
  std::vector<double> y;       // the y bins' centres
  double bulk_lo = 0.0;        // bins with bulk_lo ≤ y ≤ bulk_hi are the bulk
  double bulk_hi = 0.0;
  double mass = 1.0;           // disk mass: ρ = mass × number density
  std::vector<CouetteBlock> blocks;
};

struct Estimate {
  double value = 0.0;
  double error = 0.0;  // standard error of the mean over the blocks
};

struct CouetteResult {
  Estimate stress;       // σ_xy = (fx_high − fx_low)/2, m/τ²
  Estimate stress_low;   // −fx_low (each wall alone: equal in the steady state)
  Estimate stress_high;  // fx_high
  Estimate gradient;     // du_x/dy in the bulk, 1/τ
  Estimate density;      // bulk mass density ρ, m/σ²
  Estimate kT;
  Estimate nu;           // kinematic viscosity ν = σ/(ρ du/dy), σ²/τ
  Estimate eta;          // shear viscosity ρν = σ/(du/dy), m/τ
  std::size_t blocks = 0, bulk_bins = 0;
  std::vector<double> profile, profile_error;  // u_x(y) over all blocks, per bin
  double bulk_y = 0.0, bulk_u = 0.0;  // the bulk bins' mean y and mean u_x: the fit line's centre
};

// Throws grainflow::Error with what is wrong: fewer than 2 blocks, blocks of another size
// than y, fewer than 2 bulk bins, a bulk bin empty in a block, a zero mean gradient.
CouetteResult analyse_couette(const CouetteInput& in);

}  // namespace grainflow::scenes
