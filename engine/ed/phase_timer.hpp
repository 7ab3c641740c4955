// Phased runs (seed 003 ch. 5: "As a first stage the flow was simulated for about 8
// obstacle sizes using the value r = 1 ... Introduction of inelasticity"): a TimerAgent
// that fires at each phase's start time and calls `apply` for it, so a change of the
// collision rule, an agent's parameters or the thermostat's state lands exactly at the
// given simulated time, between two events, in one run. What the phases change lives in
// the agents they change (each saves it); the timer saves how many phases it has applied.
#pragma once
#include <cstddef>
#include <functional>
#include <vector>

#include "engine/ed/event_source.hpp"

namespace grainflow::ed {

class PhaseTimer final : public TimerAgent {
public:
  using Apply = std::function<void(SystemState&, std::size_t phase)>;
  // `times`: the phases' start times, strictly increasing and ≥ now (else
  // grainflow::Error). apply(state, k) is called at state.now() == times[k]; it may change
  // velocities (SystemState::set_velocity), the rule, agents, and ask for timers to be
  // rescheduled.
  PhaseTimer(std::vector<double> times, Apply apply, double now);
  std::string_view name() const override { return "phases"; }
  double event_time(const SystemState& state) const override;
  void action(SystemState& state) override;
  // How many phases have been applied (the rest is configuration).
  void save(io::ArchiveWriter& w) const override;
  void load(io::ArchiveReader& r) override;

  std::size_t applied() const { return next_; }  // 0 before the first phase
  const std::vector<double>& times() const { return times_; }

private:
  std::vector<double> times_;
  Apply apply_;
  std::size_t next_ = 0;
};

}  // namespace grainflow::ed
