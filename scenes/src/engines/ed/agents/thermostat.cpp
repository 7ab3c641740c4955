// The stochastic thermostat of seed 003 ch. 6 ([thermostat]): at random times, N/τ_th per
// unit time, a random disk gets its bin's time-averaged mean velocity plus a
// Maxwell–Boltzmann velocity at T_th (single, the seed's choice), or a disk and a neighbour
// get a new relative velocity keeping their centre-of-mass velocity (dual, BSS99), or one
// disk gets the system's mean plus the Maxwell velocity (global). The model as implemented:
// engine/ed/thermostat.hpp. Adds the events and the power it injects to stats.csv.
#include <algorithm>
#include <cmath>
#include <memory>

#include "engine/core/rng.hpp"
#include "engine/ed/simulation.hpp"
#include "engine/ed/thermostat.hpp"
#include "engine/io/archive.hpp"
#include "scenes/src/engines/ed/ed_agents.hpp"
#include "scenes/src/engines/ed/ed_keys.hpp"
#include "scenes/src/engines/sampling.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/scene/toml_text.hpp"

namespace grainflow::scenes {
namespace {

using namespace ed_keys;

// Bin side without an obstacle: the seed's resolution, D/10 of its D = 74 obstacle (the
// same as its 60 × 60 output grid on a 440 σ box).
constexpr double kDefaultBin = 7.4;

void declare_keys(Schema& s) {
  auto& th = s.optional_table(thermostat, "stochastic thermostat (seed 003 ch. 6): at random times a random disk gets "
                                          "the local mean velocity plus a Maxwell–Boltzmann velocity at T");
  th.add_enum(thermostat_kind, {"single", "dual", "global"}, "single",
              "single: one disk, its bin's time-averaged mean velocity + Maxwell at T (the seed's choice); dual: a "
              "disk and a neighbour keep their centre-of-mass velocity and get a relative velocity from Maxwell at T "
              "(BSS99; momentum conserved); global: one disk, the system's mean velocity + Maxwell at T");
  th.add_float(thermostat_T, 0.02, "thermostat temperature kT_th; default system.kT (with e < 1 it must exceed the "
                                   "gas's target temperature, seed Fig. 6.1)",
               "m σ²/τ²")
      .above(0.0)
      .optional();
  th.add_float(thermostat_tau, 3.48,
               "action time per disk τ_th: each disk is thermostatted once per τ_th on average (N/τ_th events per "
               "unit time; dual: N/(2 τ_th) pair events)",
               "τ")
      .above(0.0);
  th.add_float(thermostat_tau_v, 60.0,
               "single: time constant τ_th^v of the moving average of the local velocity field (sampled every "
               "τ_th^v/40)",
               "τ")
      .above(0.0);
  th.add_float(thermostat_bin, 7.4,
               "single: side l_th^v of the thermostat's own averaging bins, rounded to tile the box; default "
               "boundary.obstacle.D/10 (at least 1), else 7.4 (the seed's D/10), at most the box",
               "σ")
      .at_least(1.0)
      .optional()
      .with_note("a bin must hold disks (≥ 1 σ)");

  s.add_check([](const Scene& sc, SceneCheck& c) {
    if (!sc.has(thermostat)) return;
    const auto L = sc.get(box);
    if (auto bin = sc.find(thermostat_bin); bin && (*bin > L[0] || *bin > L[1]))
      c.fail(thermostat_bin.path, "thermostat.bin = " + toml_float(*bin) + " is larger than the box [" +
                                      toml_float(L[0]) + ", " + toml_float(L[1]) + "]; allowed: 1 ≤ bin ≤ min(Lx, Ly)");
  });
}

class ThermostatRun final : public EdAgentRun {
public:
  explicit ThermostatRun(const ed::Thermostat& t) : thermostat_(t) {}
  std::vector<StatsColumn> stats_columns() const override {
    return {{"thermostat_events", "1", "thermostat events (velocity redraws) in the stats window"},
            {"thermostat_power", "E/τ",
             "energy the thermostat put in per unit time over the stats window: Σ over its events of the change of "
             "Σ m v²/2, divided by the window length (negative when it removed energy)"}};
  }
  void stats_row(double duration, std::vector<double>& row) override {
    // Events over the window, and the energy they injected per unit time (Σ Δ(m v²/2) / t).
    const double events = double(thermostat_.events() - events_at_reset_);
    const double power = duration > 0 ? (thermostat_.energy() - energy_at_reset_) / duration : 0.0;
    events_at_reset_ = thermostat_.events();
    energy_at_reset_ = thermostat_.energy();
    row.push_back(events);
    row.push_back(power);
  }
  void figures(std::vector<std::pair<std::string, double>>& out) const override {
    out.emplace_back("thermostat_events", double(thermostat_.events()));
    out.emplace_back("thermostat_energy", thermostat_.energy());
    if (thermostat_.config().kind == ed::ThermostatKind::dual)
      out.emplace_back("thermostat_unpaired", double(thermostat_.unpaired()));
  }
  // The stats window's start (the thermostat's own state is in the engine's).
  void save(io::ArchiveWriter& w) const override {
    w.tag("thermostat.run");
    w.pod(events_at_reset_);
    w.pod(energy_at_reset_);
  }
  void load(io::ArchiveReader& r) override {
    r.tag("thermostat.run");
    r.pod(events_at_reset_);
    r.pod(energy_at_reset_);
  }

private:
  const ed::Thermostat& thermostat_;  // owned by the simulation
  std::uint64_t events_at_reset_ = 0;
  double energy_at_reset_ = 0.0;
};

std::unique_ptr<EdAgentRun> attach(const Scene& sc, ed::Simulation& sim) {
  if (!sc.has(thermostat)) return nullptr;
  const ed::Config& c = sim.config();
  ed::ThermostatConfig t;
  const std::string kind = sc.get(thermostat_kind);
  t.kind = kind == "dual" ? ed::ThermostatKind::dual : kind == "global" ? ed::ThermostatKind::global
                                                                         : ed::ThermostatKind::single;
  t.kT = sc.find(thermostat_T).value_or(c.kT);
  t.tau = sc.get(thermostat_tau);
  t.tau_v = sc.get(thermostat_tau_v);
  t.sample_interval = sample_keys::sample_interval(t.tau_v);
  double bin = kDefaultBin;
  if (auto b = sc.find(thermostat_bin)) bin = *b;
  else if (sc.has(obstacle)) bin = std::max(1.0, sc.get(obstacle_D) / 10.0);
  bin = std::min({bin, c.lx, c.ly});
  t.grid.nx = std::max(1, int(std::lround(c.lx / bin)));
  t.grid.ny = std::max(1, int(std::lround(c.ly / bin)));
  t.grid.lo = Vec2(0.0, 0.0);
  t.grid.hi = Vec2(c.lx, c.ly);
  t.seed = core::substream_seed(c.seed, 3);  // its own random stream
  return std::make_unique<ThermostatRun>(sim.emplace_timer<ed::Thermostat>(t, sim.state()));
}

}  // namespace

EdAgentEntry thermostat_agent() {
  return {"thermostat", "stochastic thermostat: single, dual or global events at N/τ_th (ch. 6)", &declare_keys,
          &attach};
}

}  // namespace grainflow::scenes
