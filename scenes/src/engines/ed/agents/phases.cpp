// Phased runs ([[phase]], seed 003 ch. 5–6: the flow is run elastic first, then the
// inelasticity is "turned on", with or without the thermostat): each [[phase]] gives its
// start time `at` and the values that change then — the normal restitution e (system.e),
// the obstacle's restitution and surface (boundary.obstacle.r, .kind), the thermostat on or off and its
// temperature (thermostat.T), a standing sound wave between the walls in y (wave_vy, §4.2:
// the speed of sound from its frequency) —, applied by an ed::PhaseTimer exactly at `at`,
// between two events, in the one run (one video, one stats.csv). Before the first phase the scene's
// own values hold. The caption of every frame names the phase in effect and its values;
// stats.csv gets the phase number and each value some phase changes, as they stand at the
// end of each row's window.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "engine/ed/circular_obstacle.hpp"
#include "engine/ed/phase_timer.hpp"
#include "engine/ed/simulation.hpp"
#include "engine/ed/thermostat.hpp"
#include "engine/io/archive.hpp"
#include "scenes/src/engines/ed/ed_agents.hpp"
#include "scenes/src/engines/ed/ed_keys.hpp"
#include "scenes/src/scene/run_keys.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/scene/toml_text.hpp"

namespace grainflow::scenes {
namespace {

using namespace ed_keys;

std::string at(std::size_t k, std::string_view key) { return fmt::format("phase[{}].{}", k, key); }

void declare_keys(Schema& s) {
  auto& p = s.array_table(phase, "a phase of the run (seed 003 ch. 5: elastic first, then inelastic): from time `at` on "
                                 "the values it gives hold, the others stay as they were");
  p.add_float(phase_at, 0.0, "simulated time the phase starts; strictly increasing from one [[phase]] to the next",
              "τ")
      .at_least(0.0)
      .required();
  p.add_string(phase_label, "", "free text naming the phase in the frames' caption (e.g. \"inelastic\")").optional();
  p.add_float(phase_e, 1.0, "system.e from now on: the normal restitution of disk–disk collisions (with e < 1 give "
                            "system.tau_tc, the TC model, or a dense gas collapses)")
      .above(0.0)
      .at_most(1.0)
      .optional();
  p.add_float(phase_obstacle_r, 1.0,
              "boundary.obstacle.r from now on: the obstacle surface's restitution (slip, noslip_flip)")
      .above(0.0)
      .at_most(1.0)
      .optional();
  p.add_enum(phase_obstacle_kind, {"slip", "noslip_thermal", "noslip_flip"}, "slip",
             "boundary.obstacle.kind from now on: the obstacle's surface (ch. 5: the dune run is elastic with the "
             "thermal no-slip obstacle, then inelastic with the random tangential flip)")
      .optional();
  p.add_bool(phase_thermostat, true, "the [thermostat] on (true) or off (false) from now on; off, it changes no "
                                     "velocity but keeps averaging the local velocity field")
      .optional();
  p.add_float(phase_thermostat_T, 0.02, "thermostat.T from now on: the thermostat temperature", "m σ²/τ²")
      .above(0.0)
      .optional();
  p.add_float_array(phase_wave_vy, {0.0, 0.0}, {"A1", "A2"},
                    "a standing sound wave between the walls in y, once at `at`: every disk's v_y += A1 sin(π y'/L') + "
                    "A2 sin(2π y'/L'), y' = y − r, L' = Ly − 2r (the span a centre reaches); stats.csv then gets "
                    "wave_vy1, wave_vy2, the projections (2/N) Σ v_y sin(kπ y'/L') (the sound_speed study)",
                    "σ/τ")
      .optional();

  s.add_check([](const Scene& sc, SceneCheck& c) {
    const std::size_t n = sc.count(phase);
    for (std::size_t k = 0; k < n; ++k) {
      const double t = sc.get(phase_at, k);
      if (k > 0 && !(t > sc.get(phase_at, k - 1)))
        c.fail(at(k, "at"), fmt::format("phase[{}].at = {} does not come after phase[{}].at = {}; allowed: strictly "
                                        "increasing times", k, toml_float(t), k - 1, toml_float(sc.get(phase_at, k - 1))));
      const std::string base = "phase[" + std::to_string(k) + "].";
      const bool e = sc.has(base + "e"), r = sc.has(base + "obstacle_r"), on = sc.has(base + "thermostat"),
                 T = sc.has(base + "thermostat_T"), wave = sc.has(base + "wave_vy"),
                 kind = sc.has(base + "obstacle_kind");
      if (!e && !r && !on && !T && !wave && !kind)
        c.fail(at(k, "at"), fmt::format("phase[{}] changes nothing; allowed: at least one of e, obstacle_r, "
                                        "obstacle_kind, thermostat, thermostat_T, wave_vy", k));
      if (wave) {
        const auto A = sc.get(phase_wave_vy, k);
        if (A[0] == 0.0 && A[1] == 0.0)
          c.fail(at(k, "wave_vy"), fmt::format("phase[{}].wave_vy = [0.0, 0.0] excites nothing; allowed: A1 or A2 ≠ 0", k));
        // sin(kπ y'/L') vanishes at both walls: the standing wave of a closed channel.
        if (sc.get(periodic)[1])
          c.fail(at(k, "wave_vy"), fmt::format("phase[{}].wave_vy is a standing wave between walls in y; allowed: with "
                                               "boundary.periodic = [_, false]", k));
      }
      for (const auto& [given, key] : {std::pair{r, "obstacle_r"}, std::pair{kind, "obstacle_kind"}})
        if (given && !sc.has(obstacle))
          c.fail(at(k, key), "phase[" + std::to_string(k) + "]." + key + " needs an obstacle; allowed: with "
                             "[boundary.obstacle]");
      if (r && sc.has(obstacle) && !obstacle_r_used(sc, k))
        c.fail(at(k, "obstacle_r"), "phase[" + std::to_string(k) + "].obstacle_r is not used by boundary.obstacle.kind "
                                    "= \"noslip_thermal\" (re-emission draws the normal speed), the surface from then "
                                    "on; allowed: \"slip\" or \"noslip_flip\" (boundary.obstacle.kind or a phase's "
                                    "obstacle_kind)");
      if (kind && sc.has(obstacle) &&
          sc.get(phase_obstacle_kind, k) == obstacle_kind_at(sc, k == 0 ? std::size_t(-1) : k - 1))
        c.fail(at(k, "obstacle_kind"), "phase[" + std::to_string(k) + "].obstacle_kind = \"" +
                                           sc.get(phase_obstacle_kind, k) + "\" is the surface already in effect; "
                                           "allowed: another of slip, noslip_thermal, noslip_flip");
      for (const auto& [given, key] : {std::pair{on, "thermostat"}, std::pair{T, "thermostat_T"}})
        if (given && !sc.has(thermostat))
          c.fail(at(k, key), "phase[" + std::to_string(k) + "]." + key + " needs a thermostat; allowed: with "
                             "[thermostat] (a phase at the start with thermostat = false keeps it off until later)");
    }
  });
}

// One [[phase]] as read from the scene: the values it sets.
struct Phase {
  double at = 0.0;
  std::string label;
  std::optional<double> e, obstacle_r, thermostat_T;
  std::optional<ed::ObstacleBoundary> obstacle_kind;
  std::optional<bool> thermostat;
  std::optional<std::array<double, 2>> wave_vy;
};

// sin(kπ y'/L') of disk i at the current time, for k = 1, 2 (phase_wave_vy's profile).
std::array<double, 2> wave_profile(const ed::SystemState& s, int i, double ly) {
  const double r = s.body[i].r;
  const double u = std::numbers::pi * (s.position_now(i).y() - r) / (ly - 2.0 * r);
  return {std::sin(u), std::sin(2.0 * u)};
}

class PhasesRun final : public EdAgentRun {
public:
  PhasesRun(std::vector<Phase> phases, ed::Simulation& sim, ed::CircularObstacle* obstacle, ed::Thermostat* thermostat)
      : phases_(std::move(phases)), sim_(sim), obstacle_(obstacle), thermostat_(thermostat) {
    for (const Phase& p : phases_) {
      changes_e_ |= p.e.has_value();
      changes_r_ |= p.obstacle_r.has_value();
      changes_kind_ |= p.obstacle_kind.has_value();
      changes_thermostat_ |= p.thermostat.has_value() || p.thermostat_T.has_value();
      has_wave_ |= p.wave_vy.has_value();
    }
    std::vector<double> times;
    for (const Phase& p : phases_) times.push_back(p.at);
    timer_ = &sim.emplace_timer<ed::PhaseTimer>(
        std::move(times), [this](ed::SystemState& s, std::size_t k) { apply(s, k); }, sim.time());
  }

  std::vector<StatsColumn> stats_columns() const override {
    const std::string at_end = ", as it stands at the end of the row's window";
    std::vector<StatsColumn> c = {{"phase", "1", "number of [[phase]] tables applied so far" + at_end}};
    if (changes_e_) c.push_back({"e", "1", "restitution of disk–disk collisions (system.e)" + at_end});
    if (changes_r_) c.push_back({"obstacle_r", "1", "restitution of the obstacle (boundary.obstacle.r)" + at_end});
    if (changes_kind_)
      c.push_back({"obstacle_kind", "1",
                   "the obstacle's surface (boundary.obstacle.kind): 0 slip, 1 noslip_thermal, 2 noslip_flip" + at_end});
    if (changes_thermostat_) {
      c.push_back({"thermostat_on", "1", "1 while the thermostat acts, 0 while a phase has switched it off" + at_end});
      c.push_back({"thermostat_T", "E", "the thermostat's temperature T_th (thermostat.T)" + at_end});
    }
    if (has_wave_)
      for (int k = 1; k <= 2; ++k)
        c.push_back({"wave_vy" + std::to_string(k), "σ/τ",
                     fmt::format("the standing wave's harmonic {0}: (2/N) Σ v_y sin({0}π y'/L') over the disks at the "
                                 "row's time (y' = y − r, L' = Ly − 2r; phase.wave_vy)", k)});
    return c;
  }
  void stats_row(double, std::vector<double>& row) override {
    row.push_back(double(timer_->applied()));
    if (changes_e_) row.push_back(sim_.restitution());
    if (changes_r_) row.push_back(obstacle_->config().restitution);
    if (changes_kind_) row.push_back(double(int(obstacle_->config().boundary)));
    if (changes_thermostat_) {
      row.push_back(thermostat_->active() ? 1.0 : 0.0);
      row.push_back(thermostat_->config().kT);
    }
    if (has_wave_) {
      const auto& s = sim_.state();
      const double ly = sim_.config().ly;
      std::array<double, 2> sum{0.0, 0.0};
      int n = 0;
      for (int i = 0; i < s.size(); ++i) {
        if (!s.present(i) || s.frozen(i)) continue;
        const auto w = wave_profile(s, i, ly);
        sum[0] += s.disk[i].vy * w[0];
        sum[1] += s.disk[i].vy * w[1];
        ++n;
      }
      for (double x : sum) row.push_back(n > 0 ? 2.0 * x / n : 0.0);
    }
  }
  void labels(std::vector<std::pair<std::string, std::string>>& out) const override {
    const std::size_t k = timer_->applied();
    std::string name = std::to_string(k);
    if (k > 0 && !phases_[k - 1].label.empty()) name += " " + phases_[k - 1].label;
    out.emplace_back("phase", name);
    if (changes_e_) out.emplace_back("e", toml_float(sim_.restitution()));
    if (changes_r_) out.emplace_back("r_obstacle", toml_float(obstacle_->config().restitution));
    if (changes_kind_) out.emplace_back("obstacle", std::string(obstacle_kind_name(obstacle_->config().boundary)));
    if (changes_thermostat_)
      out.emplace_back("thermostat", thermostat_->active() ? "T_th " + toml_float(thermostat_->config().kT) : "off");
  }
  void figures(std::vector<std::pair<std::string, double>>& out) const override {
    out.emplace_back("phases_applied", double(timer_->applied()));
  }
  // Nothing of its own: the timer keeps the phases applied, each agent what they changed.
  void save(io::ArchiveWriter& w) const override { w.tag("phases.run"); }
  void load(io::ArchiveReader& r) override { r.tag("phases.run"); }

private:
  void apply(ed::SystemState& s, std::size_t k) {
    const Phase& p = phases_[k];
    if (p.e) sim_.set_restitution(*p.e);
    if (p.obstacle_r) obstacle_->set_restitution(*p.obstacle_r);
    if (p.obstacle_kind) obstacle_->set_boundary(*p.obstacle_kind);
    if (p.thermostat_T) thermostat_->set_temperature(*p.thermostat_T);
    if (p.thermostat) thermostat_->set_active(*p.thermostat, s);
    if (p.wave_vy) {
      const double ly = sim_.config().ly;
      for (int i = 0; i < s.size(); ++i) {
        if (!s.present(i) || s.frozen(i)) continue;
        const auto w = wave_profile(s, i, ly);
        s.set_velocity(i, s.disk[i].vx, s.disk[i].vy + (*p.wave_vy)[0] * w[0] + (*p.wave_vy)[1] * w[1]);
      }
    }
  }

  std::vector<Phase> phases_;
  ed::Simulation& sim_;
  ed::CircularObstacle* obstacle_;  // owned by the simulation; nullptr: none
  ed::Thermostat* thermostat_;      // the same
  ed::PhaseTimer* timer_ = nullptr;
  bool changes_e_ = false, changes_r_ = false, changes_kind_ = false, changes_thermostat_ = false, has_wave_ = false;
};

std::unique_ptr<EdAgentRun> attach(const Scene& sc, ed::Simulation& sim) {
  const std::size_t n = sc.count(phase);
  if (n == 0) return nullptr;
  std::vector<Phase> phases(n);
  const std::optional<double> until = sc.find(run_keys::until);  // none: run.steps
  for (std::size_t k = 0; k < n; ++k) {
    Phase& p = phases[k];
    const std::string base = "phase[" + std::to_string(k) + "].";
    p.at = sc.get(phase_at, k);
    if (sc.has(base + "label")) p.label = sc.get(phase_label, k);
    if (sc.has(base + "e")) p.e = sc.get(phase_e, k);
    if (sc.has(base + "obstacle_r")) p.obstacle_r = sc.get(phase_obstacle_r, k);
    if (sc.has(base + "obstacle_kind")) p.obstacle_kind = obstacle_boundary(sc.get(phase_obstacle_kind, k));
    if (sc.has(base + "thermostat")) p.thermostat = sc.get(phase_thermostat, k);
    if (sc.has(base + "thermostat_T")) p.thermostat_T = sc.get(phase_thermostat_T, k);
    if (sc.has(base + "wave_vy")) p.wave_vy = sc.get(phase_wave_vy, k);
    if (until && p.at >= *until)
      std::fprintf(stderr, "grainflow: note: phase[%zu] starts at t = %g, at or after run.until = %g: it will not "
                           "happen in this run\n", k, p.at, *until);
    if (p.e && *p.e < 1.0 && sim.tau_tc() == 0.0 && sim.tau_tc_step() == 0.0)
      std::fprintf(stderr, "grainflow: phase[%zu].e = %g < 1 without the TC model (system.tau_tc = 0, "
                           "system.tau_tc_step = 0): a dense inelastic system collapses, and the run then fails\n",
                   k, *p.e);
  }
  ed::CircularObstacle* obstacle = nullptr;
  for (auto& a : sim.state().agents)
    if (auto* o = dynamic_cast<ed::CircularObstacle*>(a.get())) obstacle = o;
  ed::Thermostat* thermostat = nullptr;
  for (auto& t : sim.state().timers)
    if (auto* th = dynamic_cast<ed::Thermostat*>(t.get())) thermostat = th;
  return std::make_unique<PhasesRun>(std::move(phases), sim, obstacle, thermostat);
}

}  // namespace

EdAgentEntry phases_agent() {
  return {"phases", "phased runs: restitution, obstacle restitution and surface, thermostat on/off and T, a standing sound wave, at given "
          "times (ch. 5, §4.2)",
          &declare_keys, &attach};
}

}  // namespace grainflow::scenes
