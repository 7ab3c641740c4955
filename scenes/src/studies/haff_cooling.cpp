// The homogeneous cooling study (seed 003 §5.1, Fig. 5.1): a periodic box of inelastic
// disks with the TC model, started from an equilibrated elastic fluid, cools as Haff's
// law T(t) = T0 / (1 + t/t0)² with t0 = 4 / ((1 − r²) ω0), ω0 the collision frequency
// per disk at the start (the derivation: tests/ed/tc_model_test.cpp). The study measures
//   ω0   from the collisions over the early span, corrected to t = 0 (ω ∝ √T: C(s) =
//        N ω0 t0 ln(1 + s/t0) / 2 collisions by time s after the start);
//   T0, t0_fit  from a straight-line fit of T^(-1/2) = T0^(-1/2) (1 + t/t0) over the
//        early rows (t ≤ study.early · t0), T the instantaneous granular temperature;
// and checks the early cooling rate 1/t0_fit against the prediction 1/t0 (within
// study.tolerance). Later rows are compared with Haff's curve: clusters and shear bands
// make the gas cool more slowly than the law, which the ratio T/T_Haff at t = 1, 2, 5, 10 t0
// reports. Removals by the TC model's overlap cure are counted; the run is expected to
// end "complete", never stopped by the collapse guard.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/core/error.hpp"
#include "engine/io/archive.hpp"
#include "scenes/src/engines/ed/ed_keys.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/scene/schema.hpp"
#include "scenes/src/studies/study.hpp"
#include "scenes/src/studies/study_table.hpp"

namespace grainflow::scenes {
namespace {

// Optional keys (so that another study's scene setting them is refused); their defaults:
inline constexpr Key<double> early{"study.early"};
inline constexpr Key<double> tolerance{"study.tolerance"};
constexpr double kEarly = 0.1, kTolerance = 0.05;

std::string pct(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%+.2f %%", 100.0 * x);
  return b;
}

class HaffCooling final : public Study {
public:
  explicit HaffCooling(const StudyContext& c)
      : rows_("haff_cooling", c.stats_columns,
              {"kT", "kinetic_energy", "momentum_x", "momentum_y", "N", "collisions", "removed_overlap", "tau_tc"}),
        r_(c.scene.get(ed_keys::e)),
        early_(c.scene.find(early).value_or(kEarly)),
        tolerance_(c.scene.find(tolerance).value_or(kTolerance)) {}
  void stats(double time, std::span<const double> row) override { rows_.add(time, row); }
  void save(io::ArchiveWriter& w) const override { rows_.save(w); }
  void load(io::ArchiveReader& r) override { rows_.load(r); }

  StudyResult result() const override {
    const std::size_t n = rows_.size();
    if (n < 4) throw Error("haff_cooling study: " + std::to_string(n) + " stats rows; it needs at least 4 (a smaller output.stats_every)");
    const auto& t = rows_.time();
    const auto& kT = rows_.column("kT");
    const auto& ke = rows_.column("kinetic_energy");
    const auto& px = rows_.column("momentum_x");
    const auto& py = rows_.column("momentum_y");
    const auto& N = rows_.column("N");
    const auto& C = rows_.column("collisions");
    // Rows are evenly spaced; the first window started one spacing before the first row.
    const double dt = t[1] - t[0], ts = t[0] - dt;
    std::vector<double> T(n);  // instantaneous granular temperature at the row times
    for (std::size_t i = 0; i < n; ++i) T[i] = (ke[i] - 0.5 * (px[i] * px[i] + py[i] * py[i]) / N[i]) / N[i];

    // ω0 from the collisions over the early span s_e ≈ study.early · t0 (thousands of
    // them, where one window has a few hundred): with ω(s) = ω0/(1 + s/t0), C(s_e) =
    // N ω0 t0 ln(1 + s_e/t0) / 2 — a fixed point, as t0 = 4/((1 − r²) ω0) sets s_e.
    const double rate1 = 2.0 * C[0] / (N[0] * dt);
    if (!(rate1 > 0))
      throw Error("haff_cooling study: no collisions in the first stats window (t ≤ " + std::to_string(t[0]) +
                  "): nothing to measure ω0 from (a longer output.stats_every, or a denser gas)");
    double omega0 = rate1, t0 = 0, collisions_early = C[0];
    for (int it = 0; it < 100; ++it) {
      t0 = 4.0 / ((1.0 - r_ * r_) * omega0);
      std::size_t e = 0;
      while (e + 1 < n && t[e + 1] - ts <= early_ * t0 * (1 + 1e-9)) ++e;
      const double se = t[e] - ts;
      omega0 = 2.0 * C[e] / (N[e] * t0 * std::log1p(se / t0));
      collisions_early = C[e];
    }
    t0 = 4.0 / ((1.0 - r_ * r_) * omega0);

    // Straight line u = a + b s, u = T^(-1/2), s = t − ts, over the early rows.
    double S = 0, Sx = 0, Sy = 0, Sxx = 0, Sxy = 0;
    std::vector<std::pair<double, double>> pts;
    for (std::size_t i = 0; i < n; ++i) {
      const double s = t[i] - ts;
      if (s > early_ * t0 * (1 + 1e-9)) break;
      pts.emplace_back(s, 1.0 / std::sqrt(T[i]));
    }
    if (pts.size() < 3)
      throw Error("haff_cooling study: only " + std::to_string(pts.size()) + " stats rows lie within study.early · t0 = " +
                  std::to_string(early_ * t0) + "; it needs at least 3 (a smaller output.stats_every)");
    for (auto [x, y] : pts) S += 1, Sx += x, Sy += y, Sxx += x * x, Sxy += x * y;
    const double den = S * Sxx - Sx * Sx;
    const double b = (S * Sxy - Sx * Sy) / den, a = (Sy - b * Sx) / S;
    double ss = 0;
    for (auto [x, y] : pts) ss += (y - a - b * x) * (y - a - b * x);
    const double sigma2 = pts.size() > 2 ? ss / double(pts.size() - 2) : 0.0;
    const double b_err = std::sqrt(sigma2 * S / den), a_err = std::sqrt(sigma2 * Sxx / den);
    const double T0 = 1.0 / (a * a);
    const double t0_fit = a / b;
    const double t0_fit_err = t0_fit * std::hypot(a_err / a, b_err / b);
    const double rate_ratio = t0 / t0_fit;  // measured early cooling rate / Haff's
    // The fit's error and the counting error of ω0 (√C of C collisions).
    const double omega0_err = omega0 / std::sqrt(collisions_early);
    const double rate_ratio_err = rate_ratio * std::hypot(t0_fit_err / t0_fit, omega0_err / omega0);

    StudyResult res;
    auto haff = [&](double s) { return T0 / ((1 + s / t0) * (1 + s / t0)); };
    res.values = {
        {"r", r_, kNoError, "", "normal coefficient of restitution (system.e)"},
        {"N0", N[0], kNoError, "disks", "disks at the first stats row"},
        {"omega0", omega0, omega0_err, "1/τ", "collision frequency per disk at the start (from the collisions over the early span, corrected to t = 0)"},
        {"T0", T0, T0 * 2 * a_err / a, "m σ²/τ²", "initial granular temperature from the early fit"},
        {"t0_predicted", t0, t0 * omega0_err / omega0, "τ", "Haff's time 4 / ((1 − r²) ω0)"},
        {"t0_fit", t0_fit, t0_fit_err, "τ", "Haff's time fitted over t ≤ study.early · t0 (T^(-1/2) linear in t)"},
        {"early_rate_ratio", rate_ratio, rate_ratio_err, "", "measured early cooling rate / Haff's prediction (= t0 / t0_fit)"},
    };
    // Later times: T against Haff's curve where the run reached them.
    std::string late;
    for (double f : {0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0}) {
      const double target = ts + f * t0;
      if (target > t.back() + 1e-9 * target) break;
      const std::size_t i = std::size_t(std::lower_bound(t.begin(), t.end(), target - 1e-9 * target) - t.begin());
      const double ratio = T[i] / haff(t[i] - ts);
      char name[48];
      std::snprintf(name, sizeof name, "T_over_haff_at_%gt0", f);
      res.values.push_back({name, ratio, kNoError, "", "granular temperature / Haff's law at this many t0"});
      char buf[80];
      std::snprintf(buf, sizeof buf, "%s%g t0: %.3f", late.empty() ? "" : ", ", f, ratio);
      late += buf;
    }
    const double removed = rows_.column("removed_overlap").back();
    res.values.push_back({"removed_overlap", removed, kNoError, "disks", "disks removed by the TC model's overlap cure"});
    res.values.push_back({"tau_tc_final", rows_.column("tau_tc").back(), kNoError, "τ", "TC cutoff at the end"});
    res.values.push_back({"collisions_per_disk", 2.0 * C.back() / N.back(), kNoError, "", "collisions per disk in the run"});
    res.values.push_back({"t_end_over_t0", (t.back() - ts) / t0, kNoError, "", "how far the run went, in Haff times"});
    res.checks.push_back({"early cooling rate within study.tolerance of Haff's law",
                          std::abs(rate_ratio - 1.0) <= tolerance_,
                          "measured/predicted = " + std::to_string(rate_ratio) + " (" + pct(rate_ratio - 1.0) +
                              "), allowed ±" + pct(tolerance_).substr(1)});
    res.notes.push_back("T/T_Haff at " + (late.empty() ? std::string("(the run ended before 0.5 t0)") : late) +
                        (late.empty() ? "" : "; a ratio above 1 is the slower cooling of a clustering, shearing gas "
                                             "(the density fluctuations lower the collision rate of most disks)"));
    res.notes.push_back(std::to_string(long(removed)) + " disks removed as overlapping");

    // The plot: T(t) (instantaneous) and the window means against Haff's law, log-log.
    auto& f = res.figure;
    char title[160];
    std::snprintf(title, sizeof title, "Homogeneous cooling, N = %.0f, r = %g: early rate / Haff = %.3f", N[0], r_,
                  rate_ratio);
    f.title = title;
    f.x = {"t − t_start (τ)", true, {}};
    f.y = {"kT (m σ²/τ²)", true, {}};
    render::plot::Series measured, mean, law;
    measured.label = "granular temperature";
    mean.label = "window mean (stats kT)";
    mean.style = render::plot::SeriesStyle::points;
    mean.width_px = 1.5f;
    // The markers at about 12 rows per decade of time, so that they stay apart.
    double next_mark = 0;
    for (std::size_t i = 0; i < n; ++i) {
      measured.x.push_back(t[i] - ts);
      measured.y.push_back(T[i]);
      if (t[i] - ts >= next_mark) {
        mean.x.push_back(t[i] - ts - 0.5 * dt);
        mean.y.push_back(kT[i]);
        next_mark = (t[i] - ts) * std::pow(10.0, 1.0 / 12.0);
      }
    }
    law.label = "Haff: T0 / (1 + t/t0)², t0 = 4/((1−r²)ω0)";
    law.dashed = true;
    law.colour = render::Rgb{0.1f, 0.1f, 0.1f};
    law.width_px = 1.5f;
    const double s_lo = 0.5 * dt, s_hi = t.back() - ts;
    for (int k = 0; k <= 200; ++k) {
      const double s = s_lo * std::pow(s_hi / s_lo, k / 200.0);
      law.x.push_back(s);
      law.y.push_back(haff(s));
    }
    f.series = {measured, mean, law};
    return res;
  }

private:
  StatsRows rows_;
  double r_, early_, tolerance_;
};

void declare(Schema& s) {
  s.table("study")
      .add_float(early, kEarly, "haff_cooling: the early cooling rate is fitted over t ≤ early · t0 (Haff's time)")
      .above(0.0)
      .optional();
  s.table("study")
      .add_float(tolerance, kTolerance, "haff_cooling: allowed relative deviation of the early cooling rate from Haff's law")
      .above(0.0)
      .optional();
  s.add_check([](const Scene& sc, SceneCheck& c) {
    if (!sc.has(study_keys::study)) return;
    const bool mine = sc.get(study_keys::kind) == "haff_cooling";
    for (const auto* k : {&early, &tolerance})
      if (sc.has(*k) && !mine)
        c.fail(k->path, "is a key of the haff_cooling study; this scene's study is " + sc.get(study_keys::kind));
    if (mine && sc.get(ed_keys::e) >= 1.0)
      c.fail(ed_keys::e.path, "system.e = 1: an elastic gas does not cool; allowed: e < 1 for the haff_cooling study");
    if (mine && !(sc.get(ed_keys::periodic)[0] && sc.get(ed_keys::periodic)[1]))
      c.fail(ed_keys::periodic.path, "the haff_cooling study is of a homogeneous gas: boundary.periodic = [true, true]");
  });
}

std::unique_ptr<Study> open(const StudyContext& c) { return std::make_unique<HaffCooling>(c); }

}  // namespace

StudyEntry haff_cooling_study() {
  return {"haff_cooling", "kT(t) of a periodic inelastic box against Haff's law (seed 003 Fig. 5.1)", "ed", &declare,
          &open};
}

}  // namespace grainflow::scenes
