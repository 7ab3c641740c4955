// The event-source interface of seed 003 §2.5: every agent other than disk–disk pairs and
// cell walls (which are the engine's built-in fast path) provides event_time() and
// action(). Agents are registered with the engine once; the event loop never names them.
//
// Checkpoints (Simulation::save_state / load_state): every agent writes its mutable state
// with save() — random streams, positions, counters, accumulators, queued results — and
// reads it back with load(), the same values in the same order. Its configuration is not
// saved: a restored simulation constructs its agents again the same way. An agent without
// mutable state implements both empty and says why. load() may throw grainflow::Error
// (through the reader: a truncated archive, one that does not fit); the simulation then
// puts every agent back as it was.
#pragma once
#include <string_view>
#include <vector>

namespace grainflow::io {
class ArchiveWriter;
class ArchiveReader;
}  // namespace grainflow::io

namespace grainflow::ed {

class CellGrid;
class SystemState;
struct DiskNow;

// An agent that meets individual disks: elastic walls, obstacles, inlet/outlet planes.
// It lives in the cells whose disks can reach it and is asked about every disk predicted
// in those cells.
class ParticleAgent {
public:
  virtual ~ParticleAgent() = default;
  virtual std::string_view name() const = 0;
  // Cells whose disks can meet this agent before leaving the cell.
  virtual void cells(const CellGrid& grid, std::vector<int>& out) const = 0;
  // Delay from d.t until disk i, which is d then, meets the agent, or kNever. d.t is the
  // loop's clock: read it, not state.now() (the two-lane loop runs clocks of its own, and
  // asks from two threads at once: read nothing here that an action changes).
  virtual double event_time(const SystemState& state, int i, const DiskNow& d) const = 0;
  // Acts on disk i at state.now(); the disk is synchronised. Velocities are changed only
  // through SystemState::set_velocity so energy/momentum books and event counters stay right.
  // It may change disk i (velocity, frozen, removed) and the agent's own state, nothing
  // else: the two-lane loop runs it while the other lane runs (disks are added by timers).
  virtual void action(SystemState& state, int i) = 0;
  // Mutable state for checkpoints (see the top of this file).
  virtual void save(io::ArchiveWriter& w) const = 0;
  virtual void load(io::ArchiveReader& r) = 0;
};

// An agent with its own clock: sampler, thermostat, progress reporter.
class TimerAgent {
public:
  virtual ~TimerAgent() = default;
  virtual std::string_view name() const = 0;
  // Absolute time of the next action (kNever: none).
  virtual double event_time(const SystemState& state) const = 0;
  // Called at state.now() == the time returned by event_time(). Disks are not synchronised
  // (use SystemState::position_now / set_velocity).
  virtual void action(SystemState& state) = 0;
  // Mutable state for checkpoints (see the top of this file). The time of the next action
  // already scheduled is kept in the engine's event records, not asked again on load; the
  // later event_time() calls must follow from the state load() restores.
  virtual void save(io::ArchiveWriter& w) const = 0;
  virtual void load(io::ArchiveReader& r) = 0;
};

}  // namespace grainflow::ed
