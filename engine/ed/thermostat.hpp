// The stochastic thermostat of seed 003 ch. 6: a separate source of events (a TimerAgent,
// not tied to collisions, §6 "a separate source of thermostat events was introduced and
// the timing of its action was done independently"), which at random times gives a random
// disk a new velocity: the local mean velocity plus a Maxwell–Boltzmann sample at the
// thermostat's temperature T_th [AT87]. Parameters (§6): T_th, the action time per disk
// τ_th, and the time and space averaging of the local velocity field, τ_th^v and l_th^v,
// on the thermostat's own bins, independent of the output sampler's.
//
// THE MODEL, exactly as implemented
//
// Timing. Events form a Poisson process of rate N/τ_th (kinds single, global) or
// N/(2 τ_th) (kind dual), N the mobile disks (present, not frozen): each disk is
// thermostatted once per τ_th on average. After every event the next waiting time is drawn
// from the exponential distribution with that rate, N taken at the draw (in an open stream
// N changes slowly; the rate follows it event by event). With N = 0 the event does
// nothing and the next one is drawn with N = 1.
//
// The disk. Uniform over the mobile disks (rejection over the slot array: absent slots and
// frozen disks beyond the outlet filter are never chosen — those are the boundary, not the
// gas). A disk is eligible anywhere: next to walls, the obstacle, the dispenser piston or
// the filter; the loop re-predicts its events with the new velocity, and a wall or disk it
// touches is then met at once as after any collision. Only the translational velocity is
// changed (the spin of rough disks is left alone).
//
// single (the seed's choice): v_i ← V_b + ξ, ξ_x, ξ_y ~ N(0, kT_th/m_i), V_b the
//   time-averaged mean velocity of the bin holding the disk's centre. The bins: nx × ny
//   tiling the box, nx = max(1, round(Lx/l)), ny likewise (so they are as close to l as a
//   tiling allows). The time average: every `sample_interval` (from the construction
//   time on, like the field sampler's clock) each bin's momentum Σ m v and mass Σ m of the
//   mobile disks whose centres lie in it are taken, and exponential moving averages with
//   time constant τ_th^v are updated: P_b ← f P_b + (1 − f) Σ_b m v, M_b ← f M_b +
//   (1 − f) Σ_b m, f = exp(−sample_interval/τ_th^v); V_b = P_b / M_b. A sample taken Δt
//   ago weighs exp(−Δt/τ_th^v); starting from P = M = 0 the ratio needs no start-up
//   correction (both sums carry the same factor). Bins whose M_b is 0 — no sample yet, or
//   none that ever held a disk (inside the obstacle) — fall back to the global mean
//   velocity of the mobile disks at the event (the engine's momentum books). A bin partly
//   covered by a wall, the obstacle or the filter is not corrected for it: its mean comes
//   from the disks in it. Deterministic: fixed sample times, sums in slot order.
// global: the same with V = the global mean velocity of the mobile disks at the event
//   (no bins, no samples).
// dual (BSS99, seed §6: pairs chosen locally): a partner j is drawn uniformly from the
//   mobile disks in the 3 × 3 cells of the engine's cell map around disk i (i excluded;
//   periodic axes wrap), i.e. a disk within about three cell widths. The pair keeps its
//   centre-of-mass velocity c = (m_i v_i + m_j v_j)/(m_i + m_j) and gets a new relative
//   velocity g = v_i − v_j from the Maxwell–Boltzmann distribution of the relative motion
//   at T_th, g_x, g_y ~ N(0, kT_th/μ), μ = m_i m_j/(m_i + m_j):
//     v_i ← c + (m_j/(m_i + m_j)) g,   v_j ← c − (m_i/(m_i + m_j)) g.
//   Why: the pair's momentum (m_i + m_j) c is unchanged to round-off at every event (the
//   seed's "one gets ξ, the other −ξ" around a mean V conserves it only when c = V), and
//   an equilibrium pair at T_th keeps its distribution (c and g are independent Gaussians),
//   so T_th is the fixed point, as for single. For equal masses v_{i,j} = c ± g/2, each
//   disk's deviation from c has variance kT_th/(2m) per component: the pair's two
//   centre-of-mass degrees of freedom are kept, only its two relative ones are reset. Each
//   disk still takes part once per τ_th, but a pair event resets 2 degrees of freedom
//   where two single events reset 4: the energy exchange rate, and so the relaxation rate
//   of kT towards T_th, is half the single one at the same τ_th (relaxation time 2 τ_th;
//   with momentum conserved no more can be reset). No mobile partner in the 3 × 3 cells:
//   nothing changes (counted as unpaired). The bins are not used.
//
// Energy: every event's change of Σ m v²/2 is added to energy(); in an elastic system
// d(kT)/dt = (T_th − kT)/τ_th (single, global) or /(2 τ_th) (dual).
#pragma once
#include <cstdint>
#include <functional>
#include <string_view>
#include <vector>

#include "engine/core/field_grid.hpp"
#include "engine/core/rng.hpp"
#include "engine/core/vec.hpp"
#include "engine/ed/event_source.hpp"

namespace grainflow::ed {

enum class ThermostatKind { single, dual, global };
std::string_view thermostat_kind_name(ThermostatKind k);

struct ThermostatConfig {
  ThermostatKind kind = ThermostatKind::single;
  double kT = 0.02;               // T_th, energy units
  double tau = 3.48;              // τ_th: action time per disk (the seed's choice)
  double tau_v = 60.0;            // τ_th^v: time constant of the local mean (single)
  double sample_interval = 1.5;   // time between samples of the local velocity field (single)
  core::GridGeometry grid;        // the thermostat's own bins (single), usually tiling the box
  std::uint64_t seed = 1;
};

// What one event did, for tests and tracing (Thermostat::on_event).
struct ThermostatEvent {
  double t = 0.0;
  int i = -1, j = -1;            // j: the partner (dual), else -1
  Vec2 mean = Vec2::Zero();      // the mean added: V_b or the global V (single, global); c (dual)
  // The sampled part: v_i,new − mean (single, global); g = v_i,new − v_j,new (dual).
  Vec2 fluctuation = Vec2::Zero();
  bool local = false;            // single: the mean came from a bin with samples
  Vec2 vi_before = Vec2::Zero(), vi_after = Vec2::Zero(), vj_before = Vec2::Zero(), vj_after = Vec2::Zero();
  double mi = 0.0, mj = 0.0;
};

class Thermostat final : public TimerAgent {
public:
  // Draws the first waiting time with the mobile disks of `state` now; sample clock from
  // state.now(). Throws grainflow::Error for a non-positive temperature or time, or bins
  // that are not a grid (single).
  Thermostat(const ThermostatConfig& cfg, const SystemState& state);
  std::string_view name() const override { return "thermostat"; }
  double event_time(const SystemState& state) const override;
  void action(SystemState& state) override;
  // The next event's time, the sample clock, the random stream, the averaged bins, the
  // counters, and what a phase may change: on/off and T_th.
  void save(io::ArchiveWriter& w) const override;
  void load(io::ArchiveReader& r) override;

  // Phased runs (seed 003 ch. 5–6: elastic first, then the inelastic gas thermostatted).
  // Off: no velocity is changed, but the local field is still sampled (single), so that
  // the averages are ready when it is switched on; on again: the next event is drawn from
  // now (the process is memoryless). Asks the loop to reschedule this timer. Call from
  // inside an action (a phase) or between runs.
  void set_active(bool on, SystemState& state);
  bool active() const { return active_; }
  // T_th from now on (> 0, else grainflow::Error).
  void set_temperature(double kT);

  const ThermostatConfig& config() const { return cfg_; }
  std::uint64_t events() const { return events_; }      // events that changed velocities
  std::uint64_t unpaired() const { return unpaired_; }  // dual events without a partner
  std::uint64_t samples() const { return static_cast<std::uint64_t>(k_); }  // samples of the local field
  double energy() const { return energy_; }             // Σ over events of Δ(Σ m v²/2)
  // The local mean of bin b now (false: no sample yet there).
  bool bin_mean(std::size_t b, Vec2& v) const;

  // Called after every event that changed velocities (tests, tracing); empty: none.
  std::function<void(const ThermostatEvent&)> on_event;

private:
  double sample_time() const;
  void sample(SystemState& s);
  void kick(SystemState& s);
  int random_mobile(const SystemState& s);
  int random_partner(const SystemState& s, int i);
  void draw_next(const SystemState& s);

  ThermostatConfig cfg_;
  double decay_ = 0.0;     // f = exp(−interval/τ_v)
  double t_start_;
  std::int64_t k_ = 0;     // samples taken
  double next_ = 0.0;      // next event
  core::Rng rng_;
  std::vector<double> mom_, mass_;  // P_b (2 per bin), M_b
  std::vector<double> frame_mom_, frame_mass_;  // one sample's sums (scratch)
  std::vector<int> partners_;                   // dual candidates (scratch)
  std::uint64_t events_ = 0, unpaired_ = 0;
  double energy_ = 0.0;
  bool active_ = true;
};

}  // namespace grainflow::ed
