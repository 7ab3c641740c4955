// Flux velocity distributions of a stream crossing a plane (seed 003 §3.2): the fluxes F±
// against quadrature and the seed's closed forms and limits (Eq. 3.13–3.23), the densities
// and CDFs against Eq. 3.27–3.29, 3.40 and 3.47 written out literally, and the inverse-CDF
// samplers against the analytic CDFs by a Kolmogorov–Smirnov test at significance 0.001
// (fixed seeds), including one that must reject samples drawn for another stream velocity.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "engine/core/error.hpp"
#include "engine/core/rng.hpp"
#include "engine/ed/stream_flux.hpp"
#include "tests/ed/ks_statistic.hpp"

namespace ed = grainflow::ed;
using grainflow::test::ks_critical_001;
using grainflow::test::ks_statistic;

namespace {

const double kSqrtPi = std::sqrt(std::numbers::pi);

// Eq. 3.14 and 3.48 literally, with std::erf (fine for the moderate arguments used here).
double f_seed(double t) { return std::exp(-t * t) + kSqrtPi * t * (std::erf(t) + 1.0); }
double f_plus(double x0, double x1) { return std::exp(-x1 * x1) + kSqrtPi * x0 * (std::erf(x1) + 1.0); }
double f_minus(double x0, double x1) { return std::exp(-x1 * x1) + kSqrtPi * x0 * (std::erf(x1) - 1.0); }

// Composite Simpson rule with n (even) intervals.
template <class F>
double simpson(F f, double a, double b, int n) {
  const double h = (b - a) / n;
  double s = f(a) + f(b);
  for (int k = 1; k < n; ++k) s += (k % 2 ? 4.0 : 2.0) * f(a + k * h);
  return s * h / 3.0;
}

struct Case {
  double U, kT, m;
};
// U/sqrt(kT/m) = 0, 0.18 (Fig. 3.2's |a| = 0.025), 0.35, 1.4, 2.8, 7.1, and m ≠ 1.
const Case kCases[] = {{0.0, 0.02, 1.0}, {0.025, 0.02, 1.0}, {0.05, 0.02, 1.0}, {0.2, 0.02, 1.0},
                       {0.4, 0.02, 1.0}, {1.0, 0.02, 1.0},   {0.3, 1.0, 2.0}};

}  // namespace

TEST(StreamFlux, ZeroStreamClosedForm) {
  const double kT = 0.02;
  const ed::StreamFlux s(0.0, kT);
  // Eq. 3.22: F± = n / sqrt(4πc) = n sqrt(kT / (2π m)).
  const double F0 = std::sqrt(kT / (2.0 * std::numbers::pi));
  EXPECT_NEAR(s.flux_forward(), F0, 1e-15);
  EXPECT_NEAR(s.flux_backward(), F0, 1e-15);
  EXPECT_DOUBLE_EQ(s.turn_back_probability(), 1.0);
  EXPECT_EQ(s.table_cells(), 0u);  // closed form Eq. 3.43, no table
  EXPECT_EQ(s.cdf_error_bound(), 0.0);
  // Eq. 3.42/3.43: x = 1 − e^{−c y²}.
  const double c = 1.0 / (2.0 * kT);
  for (double y : {0.01, 0.1, 0.3}) {
    EXPECT_NEAR(s.cdf_forward(y), 1.0 - std::exp(-c * y * y), 1e-15);
    EXPECT_NEAR(s.quantile_forward(1.0 - std::exp(-c * y * y)), y, 1e-13);
    EXPECT_NEAR(s.cdf_backward(-y), std::exp(-c * y * y), 1e-15);
  }
}

TEST(StreamFlux, FluxesMatchQuadratureAndEq313To319) {
  for (const Case& k : kCases) {
    SCOPED_TRACE(::testing::Message() << "U=" << k.U << " kT=" << k.kT << " m=" << k.m);
    const ed::StreamFlux s(k.U, k.kT, k.m);
    const double c = k.m / (2.0 * k.kT), sc = std::sqrt(c);
    auto flux_density = [&](double w) { return std::abs(w) * std::sqrt(c / std::numbers::pi) * std::exp(-c * (w - k.U) * (w - k.U)); };
    const double span = 12.0 / sc;
    const double Fp = simpson(flux_density, 0.0, std::max(0.0, k.U) + span, 40000);
    const double Fm = simpson(flux_density, std::min(0.0, k.U - span), 0.0, 40000);
    EXPECT_NEAR(s.flux_forward(), Fp, 1e-12 * Fp);
    EXPECT_NEAR(s.flux_backward(), Fm, 1e-9 * Fm + 1e-300);
    // Eq. 3.15/3.17 literally, Eq. 3.13 for the sum, Eq. 3.19 for the net flux.
    const double norm = std::sqrt(c / std::numbers::pi) / (2.0 * c);
    const double t = sc * k.U;
    EXPECT_NEAR(s.flux_forward(), norm * f_seed(t), 1e-14);
    EXPECT_NEAR(s.flux_forward() + s.flux_backward(),
                (std::exp(-t * t) + kSqrtPi * t * std::erf(t)) / (kSqrtPi * sc), 1e-14);
    EXPECT_NEAR(s.flux_forward() - s.flux_backward(), k.U, 1e-14);
    EXPECT_NEAR(s.turn_back_probability(), s.flux_backward() / s.flux_forward(), 1e-15);
    EXPECT_LE(s.turn_back_probability(), 1.0);
    // Eq. 3.23–3.24: F+ > n U for U > 0 (reached from above).
    if (k.U > 0.0) {
      EXPECT_GT(s.flux_forward(), k.U);
    }
  }
}

TEST(StreamFlux, HighMachLimitsEq320) {
  // √c U = 25: F+ → U, F− → 0 (Eq. 3.20/3.21 read for the backward side) with the exact
  // asymptotics F− ≈ U e^{−t²} / (2 t² √π) ... evaluated without cancellation.
  const double kT = 0.02, U = 5.0;
  const ed::StreamFlux s(U, kT);
  const double t = U / std::sqrt(2.0 * kT);
  EXPECT_NEAR(s.flux_forward(), U, 1e-12);
  const double asym = std::exp(-t * t) / (2.0 * kSqrtPi * t * t) * (1.0 - 3.0 / (2.0 * t * t) + 15.0 / (4.0 * t * t * t * t)) *
                      std::sqrt(2.0 * kT) / 2.0;
  EXPECT_GT(s.flux_backward(), 0.0);
  EXPECT_NEAR(s.flux_backward() / asym, 1.0, 1e-6);
  EXPECT_LT(s.turn_back_probability(), 1e-270);
}

TEST(StreamFlux, CdfsMatchSeedEq340And347) {
  for (const Case& k : kCases) {
    SCOPED_TRACE(::testing::Message() << "U=" << k.U << " kT=" << k.kT);
    const ed::StreamFlux s(k.U, k.kT, k.m);
    const double c = k.m / (2.0 * k.kT), sc = std::sqrt(c), a = k.U, th = std::sqrt(k.kT / k.m);
    for (double q = 0.05; q < 6.0; q += 0.25) {
      const double y = a > 3 * th ? a - 3 * th + q * th : q * th;  // W_x > 0 where the mass is
      const double x340 = 1.0 - f_plus(sc * a, sc * (a - y)) / f_seed(sc * a);
      EXPECT_NEAR(s.cdf_forward(y), x340, 1e-13);
      const double yb = -q * th * 0.5;
      const double x347 = f_minus(sc * a, sc * (a - yb)) / f_minus(sc * a, sc * a);
      // Eq. 3.47's two terms cancel as √c U grows: compare at the precision it keeps.
      const double tol = 1e-13 * (1.0 + std::exp(2.0 * c * a * a));
      if (tol < 1e-6) {
        EXPECT_NEAR(s.cdf_backward(yb), x347, tol);
      }
    }
  }
}

TEST(StreamFlux, DensitiesEq327To329NormalisedAndCdfsAreTheirIntegrals) {
  for (const Case& k : kCases) {
    SCOPED_TRACE(::testing::Message() << "U=" << k.U << " kT=" << k.kT);
    const ed::StreamFlux s(k.U, k.kT, k.m);
    const double c = k.m / (2.0 * k.kT), sc = std::sqrt(c), t = sc * k.U, span = 12.0 / sc;
    // Eq. 3.27–3.29 literally at a few points.
    for (double w : {-0.3, -0.05, 0.02, 0.1, 0.45, k.U + 0.1}) {
      const double g = std::abs(w) * std::exp(-c * (w - k.U) * (w - k.U));
      EXPECT_NEAR(s.pdf_crossing(w), 2.0 * c * g / (f_seed(-t) + f_seed(t)), 1e-12 * (1 + s.pdf_crossing(w)));
      if (w > 0) {
        EXPECT_NEAR(s.pdf_forward(w), 2.0 * c * g / f_seed(t), 1e-12 * (1 + s.pdf_forward(w)));
      }
      if (w < 0 && t < 3) {
        EXPECT_NEAR(s.pdf_backward(w), 2.0 * c * g / f_seed(-t), 1e-9 * (1 + s.pdf_backward(w)));
      }
    }
    auto pf = [&](double w) { return s.pdf_forward(w); };
    auto pb = [&](double w) { return s.pdf_backward(w); };
    auto pc = [&](double w) { return s.pdf_crossing(w); };
    const double hi = k.U + span;
    // Backward mass lives within a few 1/(2c U) (high Mach) or thermal widths of 0.
    const double lo = -std::min(span, 40.0 / (2.0 * c * std::max(k.U, 1e-300)));
    EXPECT_NEAR(simpson(pf, 0.0, hi, 40000), 1.0, 1e-10);
    EXPECT_NEAR(simpson(pb, lo, 0.0, 40000), 1.0, 1e-9);
    // Eq. 3.27 has a kink at W_x = 0: integrate each side separately.
    EXPECT_NEAR(simpson(pc, -span, 0.0, 40000) + simpson(pc, 0.0, hi, 40000), 1.0, 1e-9);
    for (double frac : {0.1, 0.3, 0.5, 0.7}) {
      const double y = frac * hi;
      EXPECT_NEAR(s.cdf_forward(y), simpson(pf, 0.0, y, 20000), 1e-10);
      const double yb = frac * lo;
      EXPECT_NEAR(s.cdf_backward(yb), simpson(pb, lo, yb, 20000), 1e-9);
      EXPECT_NEAR(s.cdf_crossing(yb), simpson(pc, -span, yb, 20000), 1e-9);
    }
  }
}

TEST(StreamFlux, TabulatedQuantilesInvertTheCdfWithinTheStatedBound) {
  for (const Case& k : kCases) {
    if (k.U == 0.0) continue;
    SCOPED_TRACE(::testing::Message() << "U=" << k.U << " kT=" << k.kT);
    const ed::StreamFlux s(k.U, k.kT, k.m);
    EXPECT_EQ(s.table_cells(), 16384u);
    const double bound = s.cdf_error_bound();
    EXPECT_GT(bound, 0.0);
    EXPECT_LT(bound, 1e-5);  // far below the KS resolution 1.9/sqrt(N) at N ≤ 10^7
    double worst = 0.0;
    for (int i = 1; i < 20000; ++i) {
      const double x = i / 20000.0;
      const double wf = s.quantile_forward(x), wb = s.quantile_backward(x);
      EXPECT_GE(wf, 0.0);
      EXPECT_LE(wb, 0.0);
      worst = std::max({worst, std::abs(s.cdf_forward(wf) - x), std::abs(s.cdf_backward(wb) - x)});
    }
    std::printf("table U=%g kT=%g: worst |CDF(quantile(x)) - x| = %.3g, stated bound %.3g\n", k.U, k.kT, worst, bound);
    EXPECT_LE(worst, bound);
    // The bound is not vacuous: the interpolation error it covers is really there.
    EXPECT_GT(worst, 1e-4 * bound);
  }
}

namespace {
std::vector<double> draw(const ed::StreamFlux& s, bool forward, int component, int n, std::uint64_t seed) {
  grainflow::core::Rng rng(seed);
  std::vector<double> out(n);
  for (int i = 0; i < n; ++i) {
    const grainflow::Vec2 w = forward ? s.sample_forward(rng) : s.sample_backward(rng);
    out[i] = w[component];
  }
  return out;
}
}  // namespace

TEST(StreamFlux, SamplersFitTheFluxDistributionsKS) {
  const int n = 200000;
  const double crit = ks_critical_001(n);  // 0.00436
  std::uint64_t seed = 11;
  for (const Case& k : kCases) {
    SCOPED_TRACE(::testing::Message() << "U=" << k.U << " kT=" << k.kT << " m=" << k.m);
    const ed::StreamFlux s(k.U, k.kT, k.m);
    const double Df = ks_statistic(draw(s, true, 0, n, ++seed), [&](double w) { return s.cdf_forward(w); });
    const double Db = ks_statistic(draw(s, false, 0, n, ++seed), [&](double w) { return s.cdf_backward(w); });
    const double sd = std::sqrt(k.kT / k.m);
    auto normal_cdf = [&](double w) { return 0.5 * std::erfc(-w / (sd * std::sqrt(2.0))); };
    const double Dy = ks_statistic(draw(s, true, 1, n, ++seed), normal_cdf);
    const double Dyb = ks_statistic(draw(s, false, 1, n, ++seed), normal_cdf);
    std::printf("KS N=%d U=%g kT=%g m=%g: D(Wx+)=%.5f D(Wx-)=%.5f D(Wy+)=%.5f D(Wy-)=%.5f crit=%.5f\n", n, k.U,
                k.kT, k.m, Df, Db, Dy, Dyb, crit);
    EXPECT_LT(Df, crit) << "forward W_x";
    EXPECT_LT(Db, crit) << "backward W_x";
    EXPECT_LT(Dy, crit) << "forward W_y";
    EXPECT_LT(Dyb, crit) << "backward W_y";
  }
}

TEST(StreamFlux, KSRejectsSamplesOfAnotherStreamVelocity) {
  // The test that must fail: samples for U = 0.06 judged against the U = 0.05 CDFs.
  const int n = 200000;
  const double crit = ks_critical_001(n);
  const ed::StreamFlux right(0.05, 0.02), wrong(0.06, 0.02);
  // Power: the two CDFs differ by far more than the critical value somewhere.
  double gap_f = 0.0, gap_b = 0.0;
  for (double w = 0.0; w < 1.0; w += 1e-3) {
    gap_f = std::max(gap_f, std::abs(right.cdf_forward(w) - wrong.cdf_forward(w)));
    gap_b = std::max(gap_b, std::abs(right.cdf_backward(-w) - wrong.cdf_backward(-w)));
  }
  ASSERT_GT(gap_f, 3.0 * crit);
  ASSERT_GT(gap_b, 3.0 * crit);
  const double Df = ks_statistic(draw(wrong, true, 0, n, 5), [&](double w) { return right.cdf_forward(w); });
  const double Db = ks_statistic(draw(wrong, false, 0, n, 6), [&](double w) { return right.cdf_backward(w); });
  std::printf("KS wrong U: D(Wx+)=%.5f D(Wx-)=%.5f crit=%.5f (CDF gaps %.4f, %.4f)\n", Df, Db, crit, gap_f, gap_b);
  EXPECT_GT(Df, crit);
  EXPECT_GT(Db, crit);
  // And the zero-stream closed form must not pass for a moving stream.
  const ed::StreamFlux still(0.0, 0.02);
  EXPECT_GT(ks_statistic(draw(still, true, 0, n, 7), [&](double w) { return right.cdf_forward(w); }), crit);
}

TEST(StreamFlux, SameSeedSameVelocities) {
  const ed::StreamFlux s(0.05, 0.02);
  EXPECT_EQ(draw(s, true, 0, 1000, 3), draw(s, true, 0, 1000, 3));
  EXPECT_NE(draw(s, true, 0, 1000, 3), draw(s, true, 0, 1000, 4));
}

TEST(StreamFlux, RejectsBadParameters) {
  EXPECT_THROW(ed::StreamFlux(-0.1, 0.02), grainflow::Error);
  EXPECT_THROW(ed::StreamFlux(0.1, 0.0), grainflow::Error);
  EXPECT_THROW(ed::StreamFlux(0.1, 0.02, -1.0), grainflow::Error);
  EXPECT_THROW(ed::StreamFlux(std::nan(""), 0.02), grainflow::Error);
}
