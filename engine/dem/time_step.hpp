// Time step of the leap-frog integrator, seed 000 §2.5 (Eq. 2.21–2.23): the collision time
// of the chosen normal sub-model over n steps, and the stability limit a user-given Δt
// must respect, both asked of the chosen sub-models (contact_models.hpp). SI units.
#pragma once
#include "engine/dem/contact_params.hpp"

namespace grainflow::dem {

// Leap-frog stability limit of a spring k on reduced mass μ: 2/ω = 2 sqrt(μ/k).
double leapfrog_stability_limit(double mu_red, double k);

// For one contact type of reduced mass mu_red; m_eff_pair is the mass a restitution refers
// to, as in make_contact_law. The chosen normal model's collision time [s]; 0 when it has
// none (an overdamped spring–dashpot).
double collision_time(const ContactModelSpec& spec, const ContactParams& p, double mu_red, double m_eff_pair);
// The stability limit of the stiffest spring: the normal model's largest stiffness on μ,
// the tangential model's on 2/7 μ (a tangential force on a solid sphere's surface
// accelerates the contact point 7/2 times as much as the bare mass would).
double stability_limit(const ContactModelSpec& spec, const ContactParams& p, double mu_red);

}  // namespace grainflow::dem
