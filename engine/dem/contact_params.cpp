#include "engine/dem/contact_params.hpp"

#include <cmath>
#include <numbers>

#include "engine/core/error.hpp"

namespace grainflow::dem {

namespace {
std::string num(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}
void require(bool ok, const std::string& where, const char* key, double value, const char* allowed) {
  if (!ok) throw Error("dem: " + where + "." + key + " = " + num(value) + " is not allowed; " + allowed);
}
}  // namespace

NormalKind normal_kind_from_name(const std::string& s) {
  if (s == "walton") return NormalKind::Walton;
  if (s == "hooke") return NormalKind::Hooke;
  throw Error("dem: normal contact model \"" + s + "\" is unknown; allowed: walton, hooke");
}
TangentialKind tangential_kind_from_name(const std::string& s) {
  if (s == "walton") return TangentialKind::Walton;
  if (s == "history") return TangentialKind::History;
  if (s == "none") return TangentialKind::None;
  throw Error("dem: tangential contact model \"" + s + "\" is unknown; allowed: walton, history, none");
}
CohesionKind cohesion_kind_from_name(const std::string& s) {
  if (s == "none") return CohesionKind::None;
  if (s == "vdw") return CohesionKind::VanDerWaals;
  throw Error("dem: cohesion model \"" + s + "\" is unknown; allowed: none, vdw");
}

void validate(const ContactParams& p, const ContactModelSpec& spec, const std::string& where) {
  require(std::isfinite(p.k1) && p.k1 > 0.0, where, "k1", p.k1, "the normal stiffness must be > 0 N/m");
  if (spec.normal == NormalKind::Walton || p.gamma_n < 0.0)
    require(p.e > 0.0 && p.e <= 1.0, where, "e", p.e, "the restitution coefficient must be in (0, 1]");
  if (spec.normal == NormalKind::Hooke)
    require(std::isfinite(p.gamma_n) && (p.gamma_n >= 0.0 || p.gamma_n == -1.0), where, "gamma_n", p.gamma_n,
            "γn must be ≥ 0 1/s (or −1 to derive it from e)");
  if (spec.tangential != TangentialKind::None) {
    require(std::isfinite(p.kt) && p.kt > 0.0, where, "kt", p.kt, "the tangential stiffness must be > 0 N/m");
    require(std::isfinite(p.mu) && p.mu >= 0.0, where, "mu", p.mu, "the friction coefficient must be ≥ 0");
  }
  if (spec.tangential == TangentialKind::Walton)
    require(p.walton_gamma > 0.0 && p.walton_gamma <= 10.0, where, "walton_gamma", p.walton_gamma,
            "the exponent γ of Eq. 2.10 must be in (0, 10]");
  if (spec.cohesion == CohesionKind::VanDerWaals) {
    require(p.hamaker > 0.0, where, "hamaker", p.hamaker, "the Hamaker constant must be > 0 J");
    require(p.alpha_min > 0.0, where, "alpha_min", p.alpha_min, "the minimum separation must be > 0 m");
    require(p.alpha_cut > p.alpha_min, where, "alpha_cut", p.alpha_cut, "the cutoff must exceed alpha_min");
    require(p.r_ss >= 0.0, where, "r_ss", p.r_ss, "r_ss must be ≥ 0 m");
    require(p.vdw_radius >= 0.0, where, "vdw_radius", p.vdw_radius, "the asperity radius must be ≥ 0 m (0 = particle radius)");
  }
}

ContactParams mix(const ContactParams& a, const ContactParams& b) {
  auto m = [](double x, double y) { return 0.5 * (x + y); };
  ContactParams c = a;
  c.k1 = m(a.k1, b.k1);
  c.e = m(a.e, b.e);
  c.gamma_n = (a.gamma_n < 0.0 || b.gamma_n < 0.0) ? -1.0 : m(a.gamma_n, b.gamma_n);
  c.kt = m(a.kt, b.kt);
  c.mu = m(a.mu, b.mu);
  c.walton_gamma = m(a.walton_gamma, b.walton_gamma);
  c.gamma_t = (a.gamma_t < 0.0 || b.gamma_t < 0.0) ? -1.0 : m(a.gamma_t, b.gamma_t);
  c.damp_flag = a.damp_flag && b.damp_flag;
  c.hamaker = m(a.hamaker, b.hamaker);
  c.vdw_radius = m(a.vdw_radius, b.vdw_radius);
  c.r_ss = m(a.r_ss, b.r_ss);
  c.alpha_min = m(a.alpha_min, b.alpha_min);
  c.alpha_cut = m(a.alpha_cut, b.alpha_cut);
  return c;
}

double hooke_gamma_from_restitution(double kn, double e, double m_eff) {
  const double le = std::log(e);
  const double w0 = std::sqrt(kn / m_eff);
  return -2.0 * le * w0 / std::sqrt(std::numbers::pi * std::numbers::pi + le * le);
}

}  // namespace grainflow::dem
