// Velocity distributions of the disks of a uniform stream (velocity U along +x, temperature
// kT, mass m) that cross a plane x = const, and their inverse-CDF samplers: seed 003 §3.2.1
// (Eq. 3.12–3.29: fluxes F±, densities p, p±) and §3.2.3 (Eq. 3.40/3.43/3.47).
#pragma once
#include <cstddef>
#include <vector>

#include "engine/core/rng.hpp"
#include "engine/core/vec.hpp"

namespace grainflow::ed {

// Notation of the seed: c = m/(2kT), t = √c·U, f(t) = e^{−t²} + √π t (erf t + 1) (Eq. 3.14).
// Everything is per unit number density: multiply a flux by n (and by the plane's length L)
// to get disks per unit time. In 2D the tangential component W_y integrates out exactly as
// W_y, W_z do in the seed's 3D derivation, so the formulas are unchanged.
class StreamFlux {
public:
  // Throws grainflow::Error unless U ≥ 0 (the stream runs along +x), kT > 0, m > 0, all finite.
  StreamFlux(double U, double kT, double m = 1.0);

  double U() const { return U_; }
  double kT() const { return kT_; }
  double mass() const { return m_; }
  double c() const { return c_; }  // m / (2 kT)

  // Eq. 3.17 / 3.15 divided by n: disks per unit time per unit length (2D) per unit number
  // density crossing the plane in +x / in −x (absolute value). F+ − F− = U (Eq. 3.19);
  // U = 0: F± = sqrt(kT / (2π m)) (Eq. 3.22).
  double flux_forward() const { return F_fwd_; }
  double flux_backward() const { return F_bwd_; }
  // The low-density outlet (§3.3): of the disks reaching the outlet (flux F+) a fraction
  // F−/F+ is turned back, which reproduces the stream's back flux F− (1 at U = 0).
  double turn_back_probability() const { return p_turn_; }

  // Probability densities of W_x: all crossing disks (Eq. 3.27), forward crossers W_x > 0
  // (Eq. 3.29), backward crossers W_x < 0 (Eq. 3.28); 0 outside their support.
  double pdf_crossing(double wx) const;
  double pdf_forward(double wx) const;
  double pdf_backward(double wx) const;
  // Their cumulative distribution functions (Eq. 3.40 and 3.47, closed form).
  double cdf_crossing(double wx) const;
  double cdf_forward(double wx) const;
  double cdf_backward(double wx) const;

  // Inverse CDFs: the closed form Eq. 3.43 when U = 0, else a table of Eq. 3.40 / 3.47
  // (16384 cells in the reduced speed √c|W_x|) with linear interpolation, so that
  // cdf_forward(quantile_forward(x)) = x for x ∈ [0, 1) and
  // cdf_backward(quantile_backward(x)) = x for x ∈ (0, 1], within cdf_error_bound().
  double quantile_forward(double x) const;
  double quantile_backward(double x) const;
  // Inverse-CDF draws, one uniform deviate each.
  double sample_forward_wx(core::Rng& rng) const;   // > 0 (0 with probability ~2⁻⁵³)
  double sample_backward_wx(core::Rng& rng) const;  // < 0 (0 with probability ~2⁻⁵³)
  // Full velocity (W_x, W_y) of a disk crossing in +x / −x: W_x as above, W_y Maxwellian
  // with mean 0 and variance kT/m (the stream has no y component).
  Vec2 sample_forward(core::Rng& rng) const;
  Vec2 sample_backward(core::Rng& rng) const;

  // Upper bound on sup_w |CDF of the sampled W_x − exact CDF| for either direction: table
  // interpolation h² max|p'|/8 plus the probability beyond the table ends (0 when U = 0).
  double cdf_error_bound() const;
  std::size_t table_cells() const { return fwd_.G.empty() ? 0 : fwd_.G.size() - 1; }

private:
  // Inverse CDF of the reduced density q_τ(u) ∝ u e^{−(u−τ)²}, u ≥ 0 — the forward
  // distribution is τ = t, u = √c W_x; the backward one τ = −t, u = −√c W_x.
  struct Table {
    double tau = 0.0, u_lo = 0.0, h = 0.0, err = 0.0;
    std::vector<double> G;  // CDF at u_lo + k h
    void build(double tau, int cells);
    double invert(double x) const;
  };

  double U_, kT_, m_, c_, sc_, t_;
  double F_fwd_, F_bwd_, p_turn_;
  Table fwd_, bwd_;
};

}  // namespace grainflow::ed
