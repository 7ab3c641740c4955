// The speed of sound study's numerics (sound_speed.cpp; seed 003 §4.2): the damped-cosine
// fit of a standing wave's mode amplitude, and the adiabatic sound speed of the hard-disk
// fluid from Henderson's equation of state, which the measured speed is compared with.
#pragma once
#include <span>

namespace grainflow::scenes {

// y(t) ≈ a e^{−γt} cos(ωt + φ), a ≥ 0, ω > 0, φ in (−π, π]. Errors: one standard error
// each, from the covariance σ² (JᵀJ)⁻¹ at the optimum, σ² = Σ residual² / (n − 4) (the
// residuals taken as independent: honest when the noise is white on the rows' spacing).
struct DampedCosine {
  double a = 0, gamma = 0, omega = 0, phi = 0;
  double a_err = 0, gamma_err = 0, omega_err = 0, phi_err = 0;
  double rms = 0;  // root-mean-square residual
  int iterations = 0;
};
// Least squares by Levenberg–Marquardt from the highest peak of the periodogram (ω between
// half a cycle over the span and the rows' Nyquist frequency). `t` ascending, at least 8
// points; throws grainflow::Error otherwise, or when the fit does not converge.
DampedCosine fit_damped_cosine(std::span<const double> t, std::span<const double> y);

// Henderson 1975 (Mol. Phys. 30, 971): Z = βP/n = (1 + η²/8)/(1 − η)² for hard disks.
double henderson_z(double eta);
// Adiabatic speed of sound of hard disks (mass m) at area fraction η and temperature kT,
// with Henderson's Z: c² = (kT/m) (Z + η dZ/dη + Z²) (the derivation: sound_speed.cpp);
// the ideal gas limit is c² = 2 kT/m, γ = c_p/c_v = 2 in 2D.
double henderson_sound_speed(double eta, double kT, double m = 1.0);

}  // namespace grainflow::scenes
