// Time step of the leap-frog integrator, seed 000 §2.5: Eq. 2.21–2.23
// Δt = π e sqrt(μ/K1)/n (collision time of the stiff unloading spring over n steps),
// and the stability limit a user-given Δt must respect. SI units.
#pragma once

namespace grainflow::dem {

// Eq. 2.22: duration of a Walton collision for reduced mass mu_red: π·e·sqrt(μ/K1).
double walton_collision_time(double mu_red, double k1, double e);
// Eq. 2.23 with the reduced mass of two equal particles of mass m: π e sqrt(m/(2K1))/n.
double walton_time_step(double m, double k1, double e, int n);
// Linear spring–dashpot contact duration π/ω_d, ω_d = sqrt(kn/μ − γn²/4).
double hooke_collision_time(double mu_red, double kn, double gamma_n);
// Leap-frog stability limit of a spring k on reduced mass μ: 2/ω = 2 sqrt(μ/k).
double leapfrog_stability_limit(double mu_red, double k);

}  // namespace grainflow::dem
