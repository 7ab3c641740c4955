#include "engine/ed/phase_timer.hpp"

#include <cmath>
#include <cstdint>

#include <fmt/format.h>

#include "engine/core/error.hpp"
#include "engine/ed/system_state.hpp"
#include "engine/io/archive.hpp"

namespace grainflow::ed {

PhaseTimer::PhaseTimer(std::vector<double> times, Apply apply, double now)
    : times_(std::move(times)), apply_(std::move(apply)) {
  for (std::size_t k = 0; k < times_.size(); ++k) {
    if (!std::isfinite(times_[k]) || times_[k] < now)
      throw Error(fmt::format("ed phases: phase {} starts at t = {}; allowed: a finite time >= now ({})", k, times_[k],
                              now));
    if (k > 0 && !(times_[k] > times_[k - 1]))
      throw Error(fmt::format("ed phases: phase {} starts at t = {}, not after phase {} (t = {}); allowed: strictly "
                              "increasing times", k, times_[k], k - 1, times_[k - 1]));
  }
}

double PhaseTimer::event_time(const SystemState&) const { return next_ < times_.size() ? times_[next_] : kNever; }

void PhaseTimer::action(SystemState& s) {
  while (next_ < times_.size() && times_[next_] <= s.now()) apply_(s, next_++);
}

void PhaseTimer::save(io::ArchiveWriter& w) const {
  w.tag("phases");
  w.pod(std::uint64_t(times_.size()));
  w.pod(std::uint64_t(next_));
}

void PhaseTimer::load(io::ArchiveReader& r) {
  r.tag("phases");
  const auto n = r.get<std::uint64_t>();
  if (n != times_.size()) r.mismatch(fmt::format("{} phases in the archive, {} here", n, times_.size()));
  const auto next = r.get<std::uint64_t>();
  if (next > n) r.corrupt(fmt::format("{} of {} phases applied", next, n));
  next_ = std::size_t(next);
}

}  // namespace grainflow::ed
