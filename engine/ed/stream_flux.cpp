#include "engine/ed/stream_flux.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "engine/core/error.hpp"

namespace grainflow::ed {

namespace {

constexpr double kSqrtPi = 1.7724538509055160273;  // √π
constexpr int kTableCells = 16384;
// The tables cover the reduced speeds where the tail mass beyond either end is below
// e^{−81} ≈ 7e−36 (times a factor ≤ 2τ² + 1, see Table::build).
constexpr double kTailWidth = 9.0;

// erfcx(z) = e^{z²} erfc(z) for z ≥ 0, accurate to a few ulp·z²: the product of the exact
// square's exponential (its rounding error restored through fma) and std::erfc, and the
// asymptotic series beyond z = 26 where erfc underflows.
double erfcx(double z) {
  if (z < 26.0) {
    const double z2 = z * z;
    const double z2_err = std::fma(z, z, -z2);
    return std::exp(z2) * (1.0 + z2_err) * std::erfc(z);
  }
  const double w = 1.0 / (2.0 * z * z);
  double term = 1.0, sum = 1.0;
  for (int k = 1; k <= 8; ++k) {
    term *= -(2.0 * k - 1.0) * w;
    sum += term;
  }
  return sum / (z * kSqrtPi);
}

// Reduced density family of §3.2.1: q_τ(u) = 2u e^{−(u−τ)²} / f(τ) on u ≥ 0, with
// survival S_τ(u) = [e^{−(u−τ)²} + √π τ erfc(u − τ)] / f(τ) (Eq. 3.40/3.47 regrouped).
// For τ < 0 both terms of f and of S are tiny and cancel, so there everything is carried
// scaled by e^{τ²}: f(τ) e^{τ²} = 1 + √π τ erfcx(−τ), which only loses a factor 2τ² of
// relative precision instead of underflowing.
struct Reduced {
  double tau;
  double f;         // f(τ) (τ ≥ 0) or f(τ) e^{τ²} (τ < 0)
  explicit Reduced(double t) : tau(t) {
    f = t >= 0.0 ? std::exp(-t * t) + kSqrtPi * t * std::erfc(-t) : 1.0 + kSqrtPi * t * erfcx(-t);
  }
  // e^{−(u−τ)²}, or e^{−(u−τ)² + τ²} for τ < 0 (matching the scaling of f).
  double gauss(double u) const {
    return tau >= 0.0 ? std::exp(-(u - tau) * (u - tau)) : std::exp(-u * (u - 2.0 * tau));
  }
  double pdf(double u) const { return u <= 0.0 ? 0.0 : 2.0 * u * gauss(u) / f; }
  double dpdf(double u) const { return 2.0 * (1.0 - 2.0 * u * (u - tau)) * gauss(u) / f; }
  double survival(double u) const {
    if (u <= 0.0) return 1.0;
    const double z = u - tau;
    if (tau >= 0.0) return std::min(1.0, (std::exp(-z * z) + kSqrtPi * tau * std::erfc(z)) / f);
    return std::min(1.0, gauss(u) * (1.0 + kSqrtPi * tau * erfcx(z)) / f);
  }
};

// f(τ) itself (Eq. 3.14), for the fluxes; underflows to 0 only for τ < −26.
double f_of(double tau) {
  const Reduced r(tau);
  return tau >= 0.0 ? r.f : std::exp(-tau * tau) * r.f;
}

}  // namespace

StreamFlux::StreamFlux(double U, double kT, double m) : U_(U), kT_(kT), m_(m) {
  auto bad = [](const char* what, double v, const char* allowed) {
    std::ostringstream os;
    os << "stream flux: " << what << " = " << v << " is not allowed (" << allowed << ")";
    throw Error(os.str());
  };
  if (!std::isfinite(U) || U < 0.0) bad("stream velocity U", U, "finite, ≥ 0: the stream runs along +x");
  if (!std::isfinite(kT) || kT <= 0.0) bad("kT", kT, "finite, > 0");
  if (!std::isfinite(m) || m <= 0.0) bad("mass", m, "finite, > 0");
  c_ = m / (2.0 * kT);
  sc_ = std::sqrt(c_);
  t_ = sc_ * U;
  const double norm = 1.0 / (2.0 * kSqrtPi * sc_);  // √(c/π) / (2c), Eq. 3.15/3.17
  const double f_plus = f_of(t_), f_minus = f_of(-t_);
  F_fwd_ = norm * f_plus;
  F_bwd_ = norm * f_minus;
  p_turn_ = f_minus / f_plus;
  if (U > 0.0) {
    fwd_.build(t_, kTableCells);
    bwd_.build(-t_, kTableCells);
  }
}

void StreamFlux::Table::build(double t, int cells) {
  tau = t;
  const Reduced r(t);
  // Mass below u_lo is ≤ erfc(9)/2; above u_hi it is ≤ e^{−81}·(1 + 2τ²) for τ < 0, where
  // u_hi solves u² + 2u|τ| = 81 so the table follows the distribution's 1/(2|τ|) scale.
  u_lo = std::max(0.0, t - kTailWidth);
  const double u_hi = t >= 0.0 ? t + kTailWidth : std::sqrt(t * t + kTailWidth * kTailWidth) + t;
  h = (u_hi - u_lo) / cells;
  G.resize(static_cast<std::size_t>(cells) + 1);
  double max_dq = 0.0;
  for (int k = 0; k <= cells; ++k) {
    const double u = u_lo + k * h;
    G[k] = 1.0 - r.survival(u);
    if (k > 0) G[k] = std::max(G[k], G[k - 1]);  // round-off must not break monotonicity
    for (int j = 0; j < 4 && k < cells; ++j) max_dq = std::max(max_dq, std::abs(r.dpdf(u + 0.25 * j * h)));
  }
  // |piecewise-linear G − G| ≤ h² max|G''| / 8 with G'' = q'; the sub-sampled maximum of |q'|
  // is padded by 1 % (q' varies by O(h) between the samples); plus the tail masses and the
  // round-off of the tabulated values.
  err = h * h * max_dq * 1.01 / 8.0 + G.front() + (1.0 - G.back()) + 1e-14;
}

double StreamFlux::Table::invert(double x) const {
  const auto it = std::upper_bound(G.begin(), G.end(), x);
  if (it == G.begin()) return u_lo;
  if (it == G.end()) return u_lo + h * static_cast<double>(G.size() - 1);
  const std::size_t k = static_cast<std::size_t>(it - G.begin()) - 1;
  const double dG = G[k + 1] - G[k];
  const double frac = dG > 0.0 ? (x - G[k]) / dG : 0.0;
  return u_lo + h * (static_cast<double>(k) + frac);
}

double StreamFlux::pdf_forward(double wx) const {
  return wx <= 0.0 ? 0.0 : sc_ * Reduced(t_).pdf(sc_ * wx);
}
double StreamFlux::pdf_backward(double wx) const {
  return wx >= 0.0 ? 0.0 : sc_ * Reduced(-t_).pdf(-sc_ * wx);
}
double StreamFlux::pdf_crossing(double wx) const {
  const double wf = F_fwd_ / (F_fwd_ + F_bwd_);
  return wx > 0.0 ? wf * pdf_forward(wx) : (1.0 - wf) * pdf_backward(wx);
}
double StreamFlux::cdf_forward(double wx) const {
  return wx <= 0.0 ? 0.0 : 1.0 - Reduced(t_).survival(sc_ * wx);
}
double StreamFlux::cdf_backward(double wx) const {
  return wx >= 0.0 ? 1.0 : Reduced(-t_).survival(-sc_ * wx);
}
double StreamFlux::cdf_crossing(double wx) const {
  const double wf = F_fwd_ / (F_fwd_ + F_bwd_);
  return (1.0 - wf) * cdf_backward(wx) + wf * cdf_forward(wx);
}

double StreamFlux::quantile_forward(double x) const {
  // U = 0: x = 1 − e^{−c y²} (Eq. 3.42) inverts to y = sqrt(−ln(1 − x)/c) (Eq. 3.43).
  if (fwd_.G.empty()) return std::sqrt(-std::log1p(-x)) / sc_;
  return fwd_.invert(x) / sc_;
}
double StreamFlux::quantile_backward(double x) const {
  // P(W_x ≤ y | W_x < 0) = x: the reduced speed u = −√c y has survival x (Eq. 3.47).
  if (bwd_.G.empty()) return -std::sqrt(-std::log(x)) / sc_;
  return -bwd_.invert(1.0 - x) / sc_;
}
double StreamFlux::sample_forward_wx(core::Rng& rng) const { return quantile_forward(rng.uniform()); }
// uniform_pos() ∈ (0, 1] keeps the logarithm of the closed form finite.
double StreamFlux::sample_backward_wx(core::Rng& rng) const { return quantile_backward(rng.uniform_pos()); }
Vec2 StreamFlux::sample_forward(core::Rng& rng) const {
  const double wx = sample_forward_wx(rng);
  return {wx, std::sqrt(kT_ / m_) * rng.normal()};
}
Vec2 StreamFlux::sample_backward(core::Rng& rng) const {
  const double wx = sample_backward_wx(rng);
  return {wx, std::sqrt(kT_ / m_) * rng.normal()};
}

double StreamFlux::cdf_error_bound() const {
  return fwd_.G.empty() ? 0.0 : std::max(fwd_.err, bwd_.err);
}

}  // namespace grainflow::ed
