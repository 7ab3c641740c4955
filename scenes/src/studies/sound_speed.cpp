// The speed of sound study (seed 003 §4.2: "estimated by measuring the frequency of the
// first and second harmonics of a standing wave excited in a system (ν = 0.65, T = 0.02)
// bound by two elastic hard walls in y (periodic in x)"). The scene's one [[phase]] with
// wave_vy = [A1, A2] adds v_y += A_k sin(kπ y'/L') to every disk at its time t_w (after
// the lattice has melted); stats.csv then carries the projections
//   P_k(t) = (2/N) Σ_i v_y,i sin(kπ y'_i/L'),   y' = y − σ/2, L' = Ly − σ,
// which for a standing wave are A_k e^{−γ_k s} cos(ω_k s + φ_k), s = t − t_w (the walls are
// velocity nodes). The study fits that damped cosine to each excited harmonic's rows
// after t_w (Levenberg–Marquardt, fit_damped_cosine) and gives c_k = ω_k L'/(kπ): the
// wave number of harmonic k is kπ/L'. It compares c_k with the adiabatic speed of sound of
// Henderson's equation of state at the scene's area fraction and the temperature before the
// kick (study.henderson_tolerance), and reports the damping γ_k, whose ratio γ_2/γ_1 ≈ 4
// says the attenuation is hydrodynamic (∝ k²).
#include "scenes/src/studies/sound_speed.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <string>

#include "engine/core/error.hpp"
#include "engine/io/archive.hpp"
#include "scenes/src/engines/ed/ed_keys.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/scene/schema.hpp"
#include "scenes/src/studies/study.hpp"
#include "scenes/src/studies/study_table.hpp"

namespace grainflow::scenes {

namespace {

constexpr int kParams = 4;  // a, γ, ω, φ
using Vec4 = std::array<double, kParams>;
using Mat4 = std::array<Vec4, kParams>;

// Solves m x = b by Gaussian elimination with partial pivoting; false when singular.
bool solve4(Mat4 m, Vec4 b, Vec4& x) {
  for (int c = 0; c < kParams; ++c) {
    int p = c;
    for (int r = c + 1; r < kParams; ++r)
      if (std::abs(m[r][c]) > std::abs(m[p][c])) p = r;
    if (!(std::abs(m[p][c]) > 0)) return false;
    std::swap(m[p], m[c]);
    std::swap(b[p], b[c]);
    for (int r = c + 1; r < kParams; ++r) {
      const double f = m[r][c] / m[c][c];
      for (int k = c; k < kParams; ++k) m[r][k] -= f * m[c][k];
      b[r] -= f * b[c];
    }
  }
  for (int c = kParams - 1; c >= 0; --c) {
    double s = b[c];
    for (int k = c + 1; k < kParams; ++k) s -= m[c][k] * x[k];
    x[c] = s / m[c][c];
  }
  return true;
}

double model(const Vec4& p, double t) { return p[0] * std::exp(-p[1] * t) * std::cos(p[2] * t + p[3]); }
Vec4 gradient(const Vec4& p, double t) {
  const double e = std::exp(-p[1] * t), c = std::cos(p[2] * t + p[3]), s = std::sin(p[2] * t + p[3]);
  return {e * c, -t * p[0] * e * c, -t * p[0] * e * s, -p[0] * e * s};
}
double residual_sum(const Vec4& p, std::span<const double> t, std::span<const double> y) {
  double ss = 0;
  for (std::size_t i = 0; i < t.size(); ++i) ss += (y[i] - model(p, t[i])) * (y[i] - model(p, t[i]));
  return ss;
}

}  // namespace

DampedCosine fit_damped_cosine(std::span<const double> t, std::span<const double> y) {
  const std::size_t n = t.size();
  if (n != y.size()) throw Error("fit_damped_cosine: " + std::to_string(n) + " times, " + std::to_string(y.size()) + " values");
  if (n < 8) throw Error("fit_damped_cosine: " + std::to_string(n) + " points; it needs at least 8");
  const double span = t[n - 1] - t[0];
  if (!(span > 0)) throw Error("fit_damped_cosine: the times do not ascend");
  // The start: the periodogram's highest peak, oversampled 8× (Δω = 2π/(8 span)), from
  // half a cycle over the span to the Nyquist frequency of the mean spacing.
  const double w_lo = std::numbers::pi / span, w_hi = std::numbers::pi * double(n - 1) / span;
  const double dw = 2 * std::numbers::pi / (8 * span);
  double best = -1;
  std::complex<double> best_sum;
  Vec4 p{0, 0, w_lo, 0};
  for (double w = w_lo; w <= w_hi; w += dw) {
    std::complex<double> sum = 0;
    for (std::size_t i = 0; i < n; ++i) sum += y[i] * std::polar(1.0, -w * (t[i] - t[0]));
    if (std::norm(sum) > best) best = std::norm(sum), best_sum = sum, p[2] = w;
  }
  // y ≈ a cos(ω (t − t0) + φ0): Σ y e^{−iω(t−t0)} ≈ (n a / 2) e^{iφ0}.
  p[0] = 2 * std::abs(best_sum) / double(n);
  p[3] = std::arg(best_sum) - p[2] * t[0];

  double ss = residual_sum(p, t, y), lambda = 1e-3;
  DampedCosine out;
  Mat4 jtj{};
  for (int it = 1; it <= 500; ++it) {
    out.iterations = it;
    jtj = Mat4{};
    Vec4 jtr{};
    for (std::size_t i = 0; i < n; ++i) {
      const Vec4 g = gradient(p, t[i]);
      const double r = y[i] - model(p, t[i]);
      for (int a = 0; a < kParams; ++a) {
        jtr[a] += g[a] * r;
        for (int b = 0; b < kParams; ++b) jtj[a][b] += g[a] * g[b];
      }
    }
    bool improved = false;
    double gain = 0;
    while (lambda < 1e16) {
      Mat4 m = jtj;
      for (int a = 0; a < kParams; ++a) m[a][a] *= 1 + lambda;
      Vec4 step{};
      if (solve4(m, jtr, step)) {
        Vec4 q = p;
        for (int a = 0; a < kParams; ++a) q[a] += step[a];
        const double sq = residual_sum(q, t, y);
        if (sq <= ss) {
          gain = ss - sq;
          p = q, ss = sq, lambda = std::max(lambda / 10, 1e-12);
          improved = true;
          break;
        }
      }
      lambda *= 10;
    }
    // Converged: no step lowers the residual any more, or by less than round-off.
    if (!improved || gain <= 1e-15 * ss || ss == 0) break;
  }
  if (!std::isfinite(ss)) throw Error("fit_damped_cosine: the fit diverged");
  if (p[0] < 0) p[0] = -p[0], p[3] += std::numbers::pi;
  if (p[2] < 0) p[2] = -p[2], p[3] = -p[3];  // cos(−ωt + φ) = cos(ωt − φ)
  p[3] = std::remainder(p[3], 2 * std::numbers::pi);
  // The covariance at the optimum (JᵀJ with the final parameters).
  jtj = Mat4{};
  for (std::size_t i = 0; i < n; ++i) {
    const Vec4 g = gradient(p, t[i]);
    for (int a = 0; a < kParams; ++a)
      for (int b = 0; b < kParams; ++b) jtj[a][b] += g[a] * g[b];
  }
  const double sigma2 = ss / double(n - kParams);
  Vec4 err{};
  for (int a = 0; a < kParams; ++a) {
    Vec4 e{}, col{};
    e[a] = 1;
    err[a] = solve4(jtj, e, col) ? std::sqrt(std::max(0.0, sigma2 * col[a])) : kNoError;
  }
  out.a = p[0], out.gamma = p[1], out.omega = p[2], out.phi = p[3];
  out.a_err = err[0], out.gamma_err = err[1], out.omega_err = err[2], out.phi_err = err[3];
  out.rms = std::sqrt(ss / double(n));
  return out;
}

double henderson_z(double eta) { return (1.0 + eta * eta / 8.0) / ((1.0 - eta) * (1.0 - eta)); }

// The adiabatic sound speed of hard disks, c² = (∂P/∂ρ)_s with ρ = m n. The energy of hard
// disks is all kinetic, u = kT per disk in 2D (c_v = k), and P = n kT Z(η). At fixed
// entropy, c_v dT/T = (∂P/∂T)_n dn/n² (ds = c_v dT/T − (∂P/∂T)_v dv, v = 1/n, Maxwell), so
// (∂T/∂n)_s = T Z/n and
//   (∂P/∂n)_s = (∂P/∂n)_T + (∂P/∂T)_n (∂T/∂n)_s = kT (Z + n dZ/dn) + n k Z · T Z/n
//             = kT (Z + η dZ/dη + Z²),
// i.e. c² = (kT/m)(Z + η Z' + Z²) = γ (∂P/∂ρ)_T with γ = c_p/c_v = 1 + Z²/(Z + ηZ'). The
// ideal gas (Z = 1) gives c² = 2 kT/m, γ = 2 (2D). See e.g. Hansen & McDonald, Theory of
// Simple Liquids, §8 (c² = γ/(m n χ_T)). With Henderson's Z:
//   Z' = dZ/dη = (η/4)/(1 − η)² + 2 (1 + η²/8)/(1 − η)³.
double henderson_sound_speed(double eta, double kT, double m) {
  const double z = henderson_z(eta);
  const double dz = (eta / 4.0) / ((1.0 - eta) * (1.0 - eta)) + 2.0 * (1.0 + eta * eta / 8.0) / std::pow(1.0 - eta, 3);
  return std::sqrt(kT / m * (z + eta * dz + z * z));
}

namespace {

// Optional keys (so that another study's scene setting them is refused); their defaults:
inline constexpr Key<double> fit_span{"study.fit_span"};
inline constexpr Key<double> henderson_tolerance{"study.henderson_tolerance"};
constexpr double kHendersonTolerance = 0.15;

// The one [[phase]] with wave_vy (the scene check makes sure there is exactly one).
std::size_t wave_phase(const Scene& sc) {
  for (std::size_t k = 0; k < sc.count(ed_keys::phase); ++k)
    if (sc.has("phase[" + std::to_string(k) + "].wave_vy")) return k;
  return sc.count(ed_keys::phase);
}

std::string pct(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%+.1f %%", 100.0 * x);
  return b;
}

class SoundSpeed final : public Study {
public:
  explicit SoundSpeed(const StudyContext& c)
      : rows_("sound_speed", c.stats_columns, {"wave_vy1", "wave_vy2", "kT", "N"}),
        t_wave_(c.scene.get(ed_keys::phase_at, wave_phase(c.scene))),
        amplitude_(c.scene.get(ed_keys::phase_wave_vy, wave_phase(c.scene))),
        span_(c.scene.find(fit_span)),
        tolerance_(c.scene.find(henderson_tolerance).value_or(kHendersonTolerance)),
        eta_(ed_keys::requested_area_fraction(c.scene)),
        kT_scene_(c.scene.get(ed_keys::kT)),
        box_(c.scene.get(ed_keys::box)) {}
  void stats(double time, std::span<const double> row) override { rows_.add(time, row); }
  void save(io::ArchiveWriter& w) const override { rows_.save(w); }
  void load(io::ArchiveReader& r) override { rows_.load(r); }

  StudyResult result() const override {
    const auto& t = rows_.time();
    const double L = box_[1] - 1.0;  // L' = Ly − σ: the span the disks' centres reach
    // Before the kick: the fluid's temperature (elastic hard disks keep the scene's kT).
    double kT0 = 0;
    int before = 0;
    for (std::size_t i = 0; i < t.size(); ++i)
      if (t[i] <= t_wave_) kT0 += rows_.column("kT")[i], ++before;
    kT0 = before > 0 ? kT0 / before : kT_scene_;
    const double N0 = rows_.column("N").front();
    const double c_h = henderson_sound_speed(eta_, kT0);

    StudyResult res;
    res.values = {{"area_fraction", eta_, kNoError, "", "the scene's area fraction η (of the whole box)"},
                  {"kT_before", kT0, kNoError, "m σ²/τ²", "mean stats kT before the kick (the scene's kT when no row)"},
                  {"c_henderson", c_h, kNoError, "σ/τ",
                   "adiabatic sound speed of Henderson's equation of state, √((kT/m)(Z + η dZ/dη + Z²))"}};
    auto& f = res.figure;
    f.x = {"t − t_kick (τ)", false, {}};
    f.y = {"(2/N) Σ v_y sin(kπ y'/L') (σ/τ)", false, {}};
    double c_sum = 0, w_sum = 0;
    std::string title;
    for (int k = 1; k <= 2; ++k) {
      if (amplitude_[std::size_t(k - 1)] == 0.0) continue;
      const auto& P = rows_.column("wave_vy" + std::to_string(k));
      std::vector<double> s_all, y_all;
      for (std::size_t i = 0; i < t.size(); ++i)
        if (t[i] > t_wave_ && (!span_ || t[i] - t_wave_ <= *span_ * (1 + 1e-12))) {
          s_all.push_back(t[i] - t_wave_);
          y_all.push_back(P[i]);
        }
      if (s_all.size() < 8)
        throw Error("sound_speed study: " + std::to_string(s_all.size()) + " stats rows after the kick at t = " +
                    std::to_string(t_wave_) + " (harmonic " + std::to_string(k) +
                    "); it needs at least 8 (a smaller output.stats_every or a longer run)");
      // The mode's own thermal fluctuations, rms √(2 kT/N) (equipartition: ⟨v_y²⟩ = kT/m,
      // ⟨sin²⟩ = 1/2), ring at the same frequency with a random phase: once the kicked wave
      // has decayed into them they are no longer white noise but a second wave the fit
      // would follow. So the fit ends where its envelope a e^{−γs} falls to 3 such rms
      // (refitted until that end settles; at least two periods or all the rows).
      const double noise = std::sqrt(2.0 * kT0 / N0);
      std::vector<double> s = s_all, y = y_all;
      DampedCosine fit = fit_damped_cosine(s, y);
      for (int pass = 0; pass < 8; ++pass) {
        const double two_periods = 4 * std::numbers::pi / fit.omega;
        double end = s_all.back();
        if (fit.gamma > 0 && fit.a > 3 * noise) end = std::min(end, std::log(fit.a / (3 * noise)) / fit.gamma);
        end = std::max(end, std::min(two_periods, s_all.back()));
        std::size_t m = 0;
        while (m < s_all.size() && s_all[m] <= end) ++m;
        m = std::max<std::size_t>(m, 8);
        if (m == s.size()) break;
        s.assign(s_all.begin(), s_all.begin() + long(m));
        y.assign(y_all.begin(), y_all.begin() + long(m));
        fit = fit_damped_cosine(s, y);
      }
      const double kw = k * std::numbers::pi / L;  // the wave number
      const double c = fit.omega / kw, c_err = fit.omega_err / kw;
      const std::string h = std::to_string(k);
      res.values.push_back({"c" + h, c, c_err, "σ/τ", "speed of sound ω L'/(kπ) from harmonic " + h});
      res.values.push_back({"omega" + h, fit.omega, fit.omega_err, "1/τ", "angular frequency of harmonic " + h});
      res.values.push_back({"gamma" + h, fit.gamma, fit.gamma_err, "1/τ", "amplitude damping rate of harmonic " + h});
      res.values.push_back({"amplitude" + h, fit.a, fit.a_err, "σ/τ",
                            "fitted amplitude of harmonic " + h + " (the kick gave " +
                                std::to_string(amplitude_[std::size_t(k - 1)]) + ")"});
      res.values.push_back({"c" + h + "_over_henderson", c / c_h, c_err / c_h, "", "harmonic " + h + "'s c / Henderson's"});
      res.values.push_back({"periods" + h, fit.omega * s.back() / (2 * std::numbers::pi), kNoError, "",
                            "periods of harmonic " + h + " in the fitted span"});
      res.values.push_back({"span" + h, s.back(), kNoError, "τ",
                            "fitted span after the kick (until the envelope falls to 3 thermal rms, √(2 kT/N) each)"});
      res.checks.push_back({"c from harmonic " + h + " within study.henderson_tolerance of Henderson",
                            std::abs(c / c_h - 1.0) <= tolerance_,
                            "c" + h + " = " + std::to_string(c) + " ± " + std::to_string(c_err) + ", Henderson " +
                                std::to_string(c_h) + " (" + pct(c / c_h - 1.0) + "), allowed ±" +
                                pct(tolerance_).substr(1)});
      res.notes.push_back("harmonic " + h + ": rms residual " + std::to_string(fit.rms) + " σ/τ against amplitude " +
                          std::to_string(fit.a) + "; the error is the fit covariance's (rows taken as independent): a lower bound, as the mode's thermal "
                          "fluctuations are not white — the scatter over seeds is the honest error");
      if (c_err > 0) c_sum += c / (c_err * c_err), w_sum += 1 / (c_err * c_err);
      render::plot::Series measured, fitted;
      measured.label = "harmonic " + h;
      measured.style = render::plot::SeriesStyle::points;
      measured.colour = k == 1 ? render::Rgb{0.12f, 0.47f, 0.71f} : render::Rgb{1.0f, 0.5f, 0.05f};
      char label[96];
      std::snprintf(label, sizeof label, "fit k=%d: c = %.3f, γ = %.2g", k, c, fit.gamma);
      fitted.label = label;
      fitted.dashed = true;
      fitted.colour = render::Rgb{0.1f, 0.1f, 0.1f};
      fitted.width_px = 1.5f;
      measured.x = s_all;
      measured.y = y_all;
      for (int j = 0; j <= 600; ++j) {
        const double x = s.back() * j / 600.0;
        fitted.x.push_back(x);
        fitted.y.push_back(fit.a * std::exp(-fit.gamma * x) * std::cos(fit.omega * x + fit.phi));
      }
      f.series.push_back(measured);
      f.series.push_back(fitted);
      char part[64];
      std::snprintf(part, sizeof part, "%sc%d = %.3f", title.empty() ? "" : ", ", k, c);
      title += part;
    }
    if (w_sum > 0) {
      const double c = c_sum / w_sum, err = 1 / std::sqrt(w_sum);
      res.values.push_back({"c", c, err, "σ/τ", "the harmonics' weighted mean speed of sound"});
      res.values.push_back({"c_over_henderson", c / c_h, err / c_h, "", "c / Henderson's adiabatic sound speed"});
    }
    // The wave's energy turns into heat as it decays: at most Σ A_k²/4 per disk (2D, m = 1).
    const double heating = (amplitude_[0] * amplitude_[0] + amplitude_[1] * amplitude_[1]) / 4;
    res.notes.push_back("the kick's energy heats the gas by at most " + std::to_string(heating) + " in kT (" +
                        pct(heating / kT0).substr(1) + "; c ∝ √kT); L' = Ly − σ = " + std::to_string(L));
    char head[200];
    std::snprintf(head, sizeof head, "Standing wave, %g × %g, η = %.3g, kT = %.3g: %s (Henderson %.3f)", box_[0],
                  box_[1], eta_, kT0, title.c_str(), c_h);
    f.title = head;
    return res;
  }

private:
  StatsRows rows_;
  double t_wave_;
  std::array<double, 2> amplitude_;
  std::optional<double> span_;
  double tolerance_, eta_, kT_scene_;
  std::array<double, 2> box_;
};

void declare(Schema& s) {
  s.table("study")
      .add_float(fit_span, 0.0, "sound_speed: fit the rows up to this long after the kick (default: all of them)", "τ")
      .above(0.0)
      .optional();
  s.table("study")
      .add_float(henderson_tolerance, kHendersonTolerance,
                 "sound_speed: allowed relative deviation of each harmonic's c from Henderson's adiabatic sound speed")
      .above(0.0)
      .optional();
  s.add_check([](const Scene& sc, SceneCheck& c) {
    if (!sc.has(study_keys::study)) return;
    const bool mine = sc.get(study_keys::kind) == "sound_speed";
    for (const auto* k : {&fit_span, &henderson_tolerance})
      if (sc.has(*k) && !mine)
        c.fail(k->path, "is a key of the sound_speed study; this scene's study is " + sc.get(study_keys::kind));
    if (!mine) return;
    std::size_t waves = 0;
    for (std::size_t k = 0; k < sc.count(ed_keys::phase); ++k)
      waves += sc.has("phase[" + std::to_string(k) + "].wave_vy") ? 1 : 0;
    if (waves != 1)
      c.fail(study_keys::kind.path, "the sound_speed study needs exactly one [[phase]] with wave_vy (the standing wave's "
                                    "kick); the scene has " + std::to_string(waves));
    if (sc.get(ed_keys::periodic)[1] || !sc.get(ed_keys::periodic)[0])
      c.fail(ed_keys::periodic.path, "the sound_speed study's wave stands between walls in y, periodic in x: "
                                     "boundary.periodic = [true, false]");
    if (sc.has(ed_keys::obstacle))
      c.fail(ed_keys::obstacle.path, "the sound_speed study is of a homogeneous channel; allowed: no [boundary.obstacle]");
    if (sc.get(ed_keys::e) < 1.0 || sc.has(ed_keys::thermostat))
      c.fail(ed_keys::e.path, "the sound_speed study compares with the equation of state of elastic hard disks; "
                              "allowed: system.e = 1, no [thermostat]");
  });
}

std::unique_ptr<Study> open(const StudyContext& c) { return std::make_unique<SoundSpeed>(c); }

}  // namespace

StudyEntry sound_speed_study() {
  return {"sound_speed", "speed of sound from a standing wave between walls, against Henderson's EOS (seed 003 §4.2)",
          "ed", &declare, &open};
}

}  // namespace grainflow::scenes
