// Contact parameters of one particle group (or one pair of groups) and the names of the
// sub-models a contact law is composed from (seed 000 §2.4 Walton models, ch. 5 vdW;
// LAMMPS gran/hooke/history for comparison runs). SI units throughout.
#pragma once
#include <string>

namespace grainflow::dem {

enum class NormalKind { Walton, Hooke };
enum class TangentialKind { Walton, History, None };
enum class CohesionKind { None, VanDerWaals };

// Which sub-models make up the contact law; one law per simulation, parameters per
// group pair. Names as used in scene files: normal "walton" | "hooke", tangential
// "walton" | "history" | "none", cohesion "none" | "vdw".
struct ContactModelSpec {
  NormalKind normal = NormalKind::Walton;
  TangentialKind tangential = TangentialKind::Walton;
  CohesionKind cohesion = CohesionKind::None;
};

NormalKind normal_kind_from_name(const std::string& name);
TangentialKind tangential_kind_from_name(const std::string& name);
CohesionKind cohesion_kind_from_name(const std::string& name);

struct ContactParams {
  // Normal. Walton: K1 = loading stiffness [N/m], K2 = K1/e² (Eq. 2.9).
  // Hooke: kn [N/m]; gamma_n [1/s] (force −m_eff·γn·v_n); when gamma_n < 0 it is derived
  // from e for a pair of two equal particles of this group, exactly as LAMMPS users do.
  double k1 = 0.0;
  double e = 1.0;
  double gamma_n = -1.0;
  // Tangential. Walton: K0 = kt, μ, γ (exponent in Eq. 2.10, typically 1/3).
  // History (Cundall–Strack as LAMMPS): kt, gamma_t [1/s] (× m_eff), μ, damp_flag.
  double kt = 0.0;
  double mu = 0.0;
  double walton_gamma = 1.0 / 3.0;
  double gamma_t = -1.0;   // < 0: γn/2 (LAMMPS's NULL)
  bool damp_flag = true;   // LAMMPS dampflag: false sets γt = 0
  // Van der Waals (Eq. 5.29): Hamaker constant A [J], asperity radius R [m] (0: use the
  // particle radius), r_ss [m], α_min and α_cut [m] (surface separations).
  double hamaker = 0.0;
  double vdw_radius = 0.0;
  double r_ss = 0.0;
  double alpha_min = 0.0;
  double alpha_cut = 0.0;
};

// Throws grainflow::Error naming `where` (e.g. "groups[0].contact") when a value is
// outside its allowed range for the chosen sub-models.
void validate(const ContactParams& p, const ContactModelSpec& spec, const std::string& where);

// Arithmetic mean of two groups' parameters: the contact law between unlike groups.
ContactParams mix(const ContactParams& a, const ContactParams& b);

// LAMMPS-style γn [1/s] that gives restitution e for a linear spring kn between two
// bodies of reduced mass m_eff: γn = −2 ln e · ω0 / sqrt(π² + ln² e), ω0 = sqrt(kn/m_eff).
double hooke_gamma_from_restitution(double kn, double e, double m_eff);

}  // namespace grainflow::dem
