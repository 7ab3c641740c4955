// Public API of the 2D event-driven hard-disk engine (seed 003 ch. 2–4), what the scene
// layer drives. UNITS: disk diameter σ = 1 (length), disk mass m = 1, kT in energy units
// (time unit σ·sqrt(m/energy)); the seed's reference runs use kT = 0.02, η = 0.65.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <string_view>
#include <vector>

#include "engine/core/vec.hpp"
#include "engine/ed/circular_obstacle.hpp"
#include "engine/ed/elastic_walls.hpp"
#include "engine/ed/event_loop.hpp"
#include "engine/ed/initial_state.hpp"
#include "engine/ed/system_state.hpp"

namespace grainflow::io {
class ArchiveWriter;
class ArchiveReader;
}  // namespace grainflow::io

namespace grainflow::ed {

enum class CalendarKind {
  cell_heap,  // seed 003 §2.4: heap of cells, each holding its earliest event
  bucket,     // Paul 2007 bucket queue, one event per disk (faster; the default)
};
std::string_view calendar_name(CalendarKind k);
// "cell_heap" | "bucket"; throws grainflow::Error naming the allowed values.
CalendarKind calendar_from_name(std::string_view name);

// Threads the two-lane loop may use (Config::threads with lanes = 2): 2 where the machine has
// two cores, or what set_lane_threads said (grainflow run --threads); the results do not
// depend on it.
int lane_threads();
void set_lane_threads(int n);

struct Config {
  double lx = 40.0, ly = 40.0;      // box [0, lx] × [0, ly]
  int n = 0;                        // number of disks; 0: derived from area_fraction
  double area_fraction = 0.65;      // η = N π σ² / (4 A), used when n == 0
  double kT = 0.02;                 // initial granular temperature
  Vec2 stream{0.0, 0.0};            // stream velocity U added to Maxwell velocities
  std::uint64_t seed = 1;
  bool periodic_x = true, periodic_y = true;  // a non-periodic axis gets elastic walls
  // x is open (not periodic, no walls): stream boundary agents (dispenser piston + filter,
  // or inlet/outlet, seed 003 §3.2–3.3) close it. Needs periodic_x = false.
  bool open_x = false;
  double wall_restitution = 1.0;
  double e = 1.0, e_t = 1.0, mu = 0.0;        // §3.4 collision rule (mu = 0: smooth disks)
  // TC model (Luding & McNamara 1998, seed 003 ch. 5), with e < 1 only: a disk–disk
  // collision is elastic in its normal part (normal restitution 1; the tangential part,
  // e_t and mu, as configured) when either party's previous disk–disk collision happened
  // less than tau_tc ago. A numerical overlap removes the offending disk and raises
  // tau_tc by tau_tc_step (SystemState::remove_overlapping). Both 0: off (an inelastic
  // dense system then collapses: CollapseGuard). Time units.
  double tau_tc = 0.0, tau_tc_step = 0.0;
  // Cell edge ≥ this, and ≥ the largest diameter. Seed 003 §2.2 found 1.2σ optimal at
  // η = 0.65 for its code; with the partial rescans on crossing done here, the bucket
  // calendar runs ≈ 25 % faster at 1.0σ (bench_ed --cell), so that is the default.
  double min_cell_size = 1.0;
  CalendarKind calendar = CalendarKind::bucket;
  // lanes = 2: the box in two bands of cell rows, each with its own calendar, run on
  // `threads` threads (1 or 2; the same bits either way: ParallelLoop), with every agent,
  // timer and the TC model. lanes = 1: the one loop (threads must be 1).
  int lanes = 1, threads = 1;
};

class Simulation {
public:
  // Lattice start (triangular, melts) at η or n, Maxwell velocities at kT plus U.
  explicit Simulation(const Config& cfg);
  // Explicit disks (positions inside the box, no overlaps); velocities taken as given, and
  // their ids (DiskInit::tag) when they have them.
  Simulation(const Config& cfg, std::vector<DiskInit> disks);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  void run_until(double t);                    // all events with time ≤ t, clock ends at t
  // At most max_events of them; true when t was reached (else the clock is at the last event).
  bool run_until(double t, std::uint64_t max_events);
  std::uint64_t advance(std::uint64_t events);  // exactly that many events (fewer if none)
  // Brings every disk record to the current time (the common epoch moves to now; needed
  // before reading positions from disks()).
  void synchronise();
  double time() const { return s_.now(); }
  double next_event_time() { return loop_->next_event_time(); }

  int size() const { return s_.size(); }     // disk slots (some may be absent, §3.2–3.3)
  int count() const { return s_.count(); }   // disks present
  bool present(int i) const { return s_.present(i); }
  // Positions at state().epoch() (the current time after synchronise()), velocities.
  const HugeVector<Disk>& disks() const { return s_.disk; }
  const HugeVector<DiskBody>& bodies() const { return s_.body; }  // radius, mass, spin
  double omega(int i) const { return s_.body[i].w; }  // ω_z of disk i
  // The persistent id of the disk in slot i (SystemState::tag): what particle files call
  // `id`. Slots are memory places that open streams reuse; ids are disks.
  std::int64_t tag(int i) const { return s_.tag[i]; }
  const SystemState& state() const { return s_; }
  SystemState& state() { return s_; }
  const Config& config() const { return cfg_; }

  // Agents (§2.5). Adding one re-predicts every disk; do it before running when possible.
  // The returned pointer stays valid for the life of the simulation.
  ParticleAgent* add_agent(std::unique_ptr<ParticleAgent> agent);
  TimerAgent* add_timer(std::unique_ptr<TimerAgent> timer);
  template <class T, class... Args>
  T& emplace_timer(Args&&... args) {
    return static_cast<T&>(*add_timer(std::make_unique<T>(std::forward<Args>(args)...)));
  }

  // The box walls the non-periodic, non-open axes got at construction (nullptr: none),
  // e.g. to configure their surface and velocity (planar Couette flow) before running.
  ElasticWalls* walls();
  const ElasticWalls* walls() const;

  // Places a fixed circular obstacle, removing the disks it overlaps. Throws
  // grainflow::Error when it does not lie inside the box with a cell's margin.
  CircularObstacle& add_obstacle(const ObstacleConfig& obstacle);
  // Removes the disks for which keep(i) is false (slots renumbered, order kept; absent
  // slots are dropped too; the disks kept keep their persistent ids).
  template <class Keep>
  void remove_disks_unless(Keep keep) {
    synchronise();
    std::vector<int> kept;
    for (int i = 0; i < s_.size(); ++i)
      if (s_.present(i) && keep(i)) kept.push_back(i);
    compact(kept);
  }

  // Renumbers the disks present (frozen ones too) in the given order, each id once, e.g.
  // so that disks near each other in space lie near each other in memory, as the event
  // loop's neighbourhood scans want (a shuffled box runs 10–17 % slower than one in cell
  // order: bench_ed 160000 --order). Brings every disk to the current time and predicts
  // every event afresh: the physics is unchanged, the slot numbers (and so the order of
  // events at exactly equal times) are not; each disk keeps its persistent id (tag). Throws grainflow::Error when `order` is not such a
  // permutation. The open streams of the obstacle scenes do not need it: their refilled
  // slots keep the order banded by height, and renumbering every eighth of a pass gained
  // nothing measurable there (half a pass side by side, within ±2 %).
  void reorder_disks(const std::vector<int>& order);
  // The ids of the disks present in cell order (cells row by row, ids ascending within a
  // cell), for reorder_disks.
  std::vector<int> cell_order() const;

  // Measurements over the window since the last reset (construction starts one).
  const Stats& stats() const { return s_.stats; }
  EventLoopBase::LaneRuns lane_runs() const { return loop_->lane_runs(); }
  Observables observables() const { return s_.observables(); }
  void reset_measurements() { s_.reset_measurements(); }
  // Exact totals from the disks (not the incremental books); frozen disks are left out.
  double kinetic_energy() const;   // Σ m v²/2 + Σ I ω²/2
  Vec2 momentum() const;
  double area_fraction() const;    // of the disks present (frozen included)
  // Minimum over all pairs of (distance − σ_ij) at the current time, O(N²)/cells: for tests.
  double min_gap() const;

  // ---- collision rule at run time; TC model ------------------------------------------
  // Normal restitution from now on, in [0, 1] (else grainflow::Error): phased runs (an
  // elastic equilibration, then inelastic cooling). No event changes (the rule decides no
  // prediction). A checkpoint keeps the value; config().e stays the constructed one.
  void set_restitution(double e);
  double restitution() const { return s_.rule.e; }
  // The TC model's cutoff τ_TC and its step from now on (both ≥ 0, else grainflow::Error).
  void set_time_cutoff(double tau_tc, double tau_tc_step);
  double tau_tc() const { return s_.tc.tau; }              // current (raised by removals)
  double tau_tc_step() const { return s_.tc.step; }
  bool time_cutoff_on() const { return s_.tc_on(); }       // e < 1 and a cutoff configured
  // Disks removed as numerically overlapping (TC model), and each removal in order.
  std::uint64_t overlap_removals() const { return s_.stats.removed_overlap; }
  const std::vector<OverlapRemoval>& overlap_log() const { return s_.overlap_log; }

  // Every collision is reported (tests, tracing); an empty function turns it off.
  void set_collision_observer(std::function<void(const CollisionRecord&)> f) { loop_->on_collision = std::move(f); }

  const char* calendar() const { return loop_->calendar_name(); }
  std::size_t memory_bytes() const;  // engine state incl. calendar, excluding agents
  // memory_bytes() array by array, each with whether the event loop touches it (hot: the
  // disk records a scan reads, event records, counters, the cell map and the calendar; the
  // bodies unless the disks are plain and no agent or frozen disk is present; the slot
  // states while an agent, a timer or a frozen disk is; the TC times while the TC model
  // is on) or not (cold: persistent ids).
  struct MemoryPart {
    const char* name;
    std::size_t bytes;
    bool hot;
  };
  std::vector<MemoryPart> memory_parts() const;

  // ---- checkpoints --------------------------------------------------------------------
  // Writes the complete mutable state — SystemState (disks at their own times, counters,
  // slots, free list, event records, cell membership, books, stats, unsettled outside
  // changes, the TC model's restitution, cutoff, last-collision times and log) and every agent's and timer's save() — so that a simulation restored from it
  // continues bit for bit, as if never interrupted. Call between runs (not from inside an
  // agent's action). The configuration is not saved, only what must match: box and
  // boundaries, collision rule as constructed, cell size, calendar kind, the number of disks built with,
  // the cell grid, and the agents' and timers' names in order.
  void save_state(io::ArchiveWriter& w) const;
  // Restores such a state into a simulation constructed the same way (same Config, same
  // disks count, the same agents and timers added in the same order; run or not: all
  // mutable state is overwritten, the disk arrays take the saved size, grown by open
  // boundaries or not). The calendar is rebuilt from the saved event records without
  // predicting anything. Throws grainflow::Error when the archive does not fit — another
  // box, boundaries, collision rule, cell grid, disk count or calendar kind ("does not
  // match"), other agents or timers or another order, inconsistent arrays ("is corrupt"),
  // a truncated archive ("is truncated") — and leaves the simulation as it was.
  // Reads up to the end of this state, not necessarily of the archive.
  void load_state(io::ArchiveReader& r);

private:
  void build(std::vector<DiskInit> disks);
  void assign_tags(const std::vector<DiskInit>& disks);
  void restart();
  void compact(const std::vector<int>& kept);

  Config cfg_;
  int n_built_ = 0;  // disks given to build() (checkpoints compare it)
  SystemState s_;
  std::unique_ptr<EventLoopBase> loop_;
};

// Inelastic collapse (McNamara & Young 1994) as a caller sees it: events go on, the clock
// stops. Fed after each bounded run (Simulation::run_until(t, max_events), advance), it
// closes a window once `window` events have passed since the last one, and reports the
// collapse when over that window the simulated time per event fell below `ratio` times
// the simulation's average so far (time() / events since t = 0): events per unit
// simulated time 10^6 times the run's average, by default. A healthy gas, even cooling or
// compressed, stays within a factor of a few hundred; a collapse stalls the clock at
// its limit point within a few hundred collisions, after which the ratio is ~0. It
// decides nothing in the simulation (no bit of a run depends on it).
class CollapseGuard {
public:
  explicit CollapseGuard(std::uint64_t window = 10'000'000, double ratio = 1e-6) : window_(window), ratio_(ratio) {}
  // True when the window just closed shows a collapse. window == 0: never.
  bool collapsed(const Simulation& sim);
  // The window in progress (for checkpoints: a restored guard continues it).
  std::uint64_t window_events() const { return events0_; }
  double window_time() const { return t0_; }
  void set_window_start(std::uint64_t events, double t) { events0_ = events; t0_ = t; }
  // Of the last closed window: events per unit simulated time, and the run's average.
  double rate() const { return rate_; }
  double average_rate() const { return average_; }

private:
  std::uint64_t window_, events0_ = 0;
  double ratio_, t0_ = 0.0, rate_ = 0.0, average_ = 0.0;
};

}  // namespace grainflow::ed
