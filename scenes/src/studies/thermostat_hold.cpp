// The thermostat hold study (seed 003 ch. 6, Fig. 6.1): a periodic box of inelastic disks
// (TC model) with the stochastic thermostat at T_th reaches a steady kT where the energy
// the thermostat injects, (T_th − kT)/τ_th per disk and unit time, balances what the
// collisions dissipate, (1 − r²) ω kT / 2 with ω ∝ √kT. One run measures, after
// study.settle time units,
//   kT_held ± its block-average error, and whether it is within study.tolerance of
//           study.target_kT;
//   T_th_needed = T* + (T_th − kT)(T*/kT)^(3/2): the thermostat temperature that holds the
//           target T* — the measured balance moved along the cooling law (∝ kT^(3/2));
//           exact when kT = T*, a small correction near it;
//   T_th_theory = T* + τ_th (1 − r²) ω(T*) T*/2, from the measured collision frequency
//           (dual: twice the excess, its pair events exchange energy at half the rate);
//   heating_efficiency: the measured power / (N (T_th − kT)/τ_th) (1 for the plain model);
//   the total momentum's random walk: <|P(t) − P(settle)|²> / (t − settle), which the
//           dual variant keeps at round-off; the single one resamples momentum, so P
//           fluctuates on the scale √(2 N kT_th) and wanders as the bins' mean follows it.
// A sweep over τ_th (Fig. 6.1) is one run per τ_th (independent processes; `grainflow
// plot --rows` draws the T_th_needed of their study.json files against τ_th).
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

inline constexpr Key<double> target_kT{"study.target_kT"};
inline constexpr Key<double> settle{"study.settle"};
inline constexpr Key<double> hold_tolerance{"study.hold_tolerance"};
// Their defaults (the keys are optional, so that another study's scene setting them is refused).
constexpr double kTarget = 0.02, kSettle = 50.0, kHoldTolerance = 0.05;

class ThermostatHold final : public Study {
public:
  explicit ThermostatHold(const StudyContext& c)
      : rows_("thermostat_hold", c.stats_columns,
              {"kT", "N", "collisions", "momentum_x", "momentum_y", "thermostat_power", "thermostat_events",
               "removed_overlap"}),
        r_(c.scene.get(ed_keys::e)),
        T_th_(c.scene.find(ed_keys::thermostat_T).value_or(c.scene.get(ed_keys::kT))),
        tau_th_(c.scene.get(ed_keys::thermostat_tau)),
        kind_(c.scene.get(ed_keys::thermostat_kind)),
        target_(c.scene.find(target_kT).value_or(kTarget)),
        settle_(c.scene.find(settle).value_or(kSettle)),
        tolerance_(c.scene.find(hold_tolerance).value_or(kHoldTolerance)) {}
  void stats(double time, std::span<const double> row) override { rows_.add(time, row); }
  void save(io::ArchiveWriter& w) const override { rows_.save(w); }
  void load(io::ArchiveReader& r) override { rows_.load(r); }

  StudyResult result() const override {
    const auto& t = rows_.time();
    const std::size_t n = t.size();
    const std::size_t first =
        rows_.first_row_after(settle_, 16, "study.settle", "a longer run.until or a smaller output.stats_every");
    auto tail = [&](const char* name) {
      const auto& c = rows_.column(name);
      return std::span<const double>(c.data() + first, n - first);
    };
    const auto kT = tail("kT"), N = tail("N"), power = tail("thermostat_power"), C = tail("collisions");
    const double dt = t[1] - t[0];
    const MeanError held = block_mean(kT);
    std::vector<double> p_per(power.size());
    for (std::size_t i = 0; i < power.size(); ++i) p_per[i] = power[i] / N[i];
    const MeanError heat = block_mean(p_per);
    // Collision frequency per disk over the held part (collisions are cumulative).
    const auto& Call = rows_.column("collisions");
    const double c0 = first > 0 ? Call[first - 1] : 0.0, t_from = first > 0 ? t[first - 1] : t[0] - dt;
    const double omega = 2.0 * (C.back() - c0) / (N.back() * (t.back() - t_from));

    const double T = held.mean, Ts = target_;
    const double scale = std::pow(Ts / T, 1.5);
    const double needed = Ts + (T_th_ - T) * scale;
    const double dneeded_dT = -scale - 1.5 * (T_th_ - T) * scale / T;
    const double needed_err = std::abs(dneeded_dT) * held.error;
    // A dual event resets 2 of a pair's 4 degrees of freedom: half the single exchange rate.
    const double exchange = kind_ == "dual" ? 0.5 : 1.0;
    const double theory = Ts + tau_th_ * (1.0 - r_ * r_) * omega * std::sqrt(Ts / T) * Ts / (2.0 * exchange);
    const double efficiency = heat.mean * tau_th_ / (T_th_ - T);
    const double deviation = T / Ts - 1.0;

    // Momentum random walk: |P(t) − P(settle)|² against t − settle, slope through 0.
    const auto px = tail("momentum_x"), py = tail("momentum_y");
    double sxy = 0, sxx = 0, p2 = 0;
    for (std::size_t i = 0; i < px.size(); ++i) {
      const double s = t[first + i] - t[first];
      const double d2 = (px[i] - px[0]) * (px[i] - px[0]) + (py[i] - py[0]) * (py[i] - py[0]);
      sxy += s * d2;
      sxx += s * s;
      p2 += px[i] * px[i] + py[i] * py[i];
    }
    const double walk = sxx > 0 ? sxy / sxx : 0.0;
    // A gas whose disks were all just thermostatted has |P|² = N · 2 kT_th (m = 1): the scale
    // of the single variant's fluctuation, which its bins' mean then lets wander slowly.
    const double rms_fresh = std::sqrt(2.0 * T_th_ / N.back());

    StudyResult res;
    res.values = {
        {"r", r_, kNoError, "", "normal coefficient of restitution (system.e)"},
        {"tau_th", tau_th_, kNoError, "τ", "thermostat action time per disk"},
        {"T_th", T_th_, kNoError, "m σ²/τ²", "thermostat temperature of this run"},
        {"kT_held", T, held.error, "m σ²/τ²", "mean kT after study.settle (block-average error)"},
        {"kT_deviation", deviation, held.error / Ts, "", "kT_held / target_kT − 1"},
        {"T_th_needed", needed, needed_err, "m σ²/τ²", "thermostat temperature that holds target_kT (balance moved along kT^(3/2))"},
        {"T_th_theory", theory, kNoError, "m σ²/τ²", "T* + τ_th (1 − r²) ω(T*) T*/2 (dual: twice the excess) from the measured ω"},
        {"omega", omega, kNoError, "1/τ", "collision frequency per disk while held"},
        {"heating_power_per_disk", heat.mean, heat.error, "m σ²/τ³", "energy the thermostat injects per disk and unit time"},
        {"heating_efficiency", efficiency, kNoError, "", "measured power / ((T_th − kT)/τ_th) per disk"},
        {"momentum_walk", walk, kNoError, "m² σ²/τ³", "growth of |P(t) − P(settle)|² per unit time (total momentum)"},
        {"momentum_rms_fresh", rms_fresh, kNoError, "m σ/τ", "√(2 kT_th / N): |P|/N of independent Maxwell velocities"},
        {"momentum_rms_per_disk", std::sqrt(p2 / double(px.size())) / N.back(), kNoError, "m σ/τ",
         "rms of the total momentum / N while held"},
        {"removed_overlap", rows_.column("removed_overlap").back(), kNoError, "disks", "removed by the TC overlap cure"},
    };
    char detail[160];
    std::snprintf(detail, sizeof detail, "kT = %.5g ± %.2g against %.5g: %+.2f %%, allowed ±%.3g %%", T, held.error, Ts,
                  100 * deviation, 100 * tolerance_);
    res.checks.push_back({"kT held within study.hold_tolerance of study.target_kT", std::abs(deviation) <= tolerance_,
                          detail});
    res.notes.push_back("thermostat kind " + kind_ + ": |P(t) − P(settle)|² grows by " + std::to_string(walk) +
                        " per unit time; single/global resample momentum (P relaxes to the bins' mean in τ_th and "
                        "wanders with it), dual conserves it to round-off");

    auto& f = res.figure;
    char title[160];
    std::snprintf(title, sizeof title, "Thermostat (%s) r = %g, τ_th = %g, T_th = %g: kT = %.4g", kind_.c_str(), r_,
                  tau_th_, T_th_, T);
    f.title = title;
    f.x = {"t (τ)", false, {}};
    f.y = {"kT (m σ²/τ²)", false, {}};
    render::plot::Series measured, target, lo, hi;
    measured.label = "kT (stats window mean)";
    for (std::size_t i = 0; i < n; ++i) {
      measured.x.push_back(t[i] - 0.5 * dt);
      measured.y.push_back(rows_.column("kT")[i]);
    }
    const double x0 = t.front() - dt, x1 = t.back();
    target.label = "target kT";
    target.x = {x0, x1};
    target.y = {Ts, Ts};
    target.colour = render::Rgb{0.1f, 0.1f, 0.1f};
    target.width_px = 1.5f;
    lo.label = "target ± tolerance";
    lo.dashed = hi.dashed = true;
    lo.colour = hi.colour = render::Rgb{0.5f, 0.5f, 0.5f};
    lo.width_px = hi.width_px = 1.25f;
    lo.x = hi.x = {x0, x1};
    lo.y = {Ts * (1 - tolerance_), Ts * (1 - tolerance_)};
    hi.y = {Ts * (1 + tolerance_), Ts * (1 + tolerance_)};
    f.series = {measured, target, lo, hi};
    return res;
  }

private:
  StatsRows rows_;
  double r_, T_th_, tau_th_;
  std::string kind_;
  double target_, settle_, tolerance_;
};

void declare(Schema& s) {
  s.table("study")
      .add_float(target_kT, kTarget, "thermostat_hold: the granular temperature the thermostat should hold", "m σ²/τ²")
      .above(0.0)
      .optional();
  s.table("study")
      .add_float(settle, kSettle, "thermostat_hold: stats rows up to this time are the approach, not the steady state", "τ")
      .at_least(0.0)
      .optional();
  s.table("study")
      .add_float(hold_tolerance, kHoldTolerance, "thermostat_hold: allowed relative deviation of kT from target_kT")
      .above(0.0)
      .optional();
  s.add_check([](const Scene& sc, SceneCheck& c) {
    if (!sc.has(study_keys::study)) return;
    const bool mine = sc.get(study_keys::kind) == "thermostat_hold";
    for (const auto* k : {&target_kT, &settle, &hold_tolerance})
      if (sc.has(*k) && !mine)
        c.fail(k->path, "is a key of the thermostat_hold study; this scene's study is " + sc.get(study_keys::kind));
    if (mine && !sc.has(ed_keys::thermostat))
      c.fail(study_keys::kind.path, "the thermostat_hold study needs a [thermostat] section");
  });
}

std::unique_ptr<Study> open(const StudyContext& c) { return std::make_unique<ThermostatHold>(c); }

}  // namespace

StudyEntry thermostat_hold_study() {
  return {"thermostat_hold", "kT held by the stochastic thermostat and the T_th that holds a target (seed 003 Fig. 6.1)",
          "ed", &declare, &open};
}

}  // namespace grainflow::scenes
