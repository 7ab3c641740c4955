// Ctrl-C handling for long runs (ARCHITECTURE.md, "Errors"): the first SIGINT/SIGTERM sets
// a stop flag the run loop polls, so the run finalises what it has (stats.csv, MP4, run.json
// "interrupted"); a second one kills the process the default way.
#pragma once
#include <atomic>
#include <csignal>

namespace grainflow::scenes {

// Set by the handler; lock-free, so reading it from the run loop is safe and cheap.
const std::atomic<bool>& stop_flag() noexcept;
inline bool stop_requested() noexcept { return stop_flag().load(std::memory_order_relaxed); }
// The signal that set the flag (SIGINT, SIGTERM), 0 if none.
int stop_signal() noexcept;
// Clears the flag (a new run in the same process, tests).
void clear_stop() noexcept;

// Installs the handlers for its lifetime and restores the previous ones afterwards.
// The handler prints one line on stderr, sets the flag and resets itself to the default
// action (SA_RESETHAND), so a second Ctrl-C terminates at once.
class InterruptGuard {
public:
  InterruptGuard();
  ~InterruptGuard();
  InterruptGuard(const InterruptGuard&) = delete;
  InterruptGuard& operator=(const InterruptGuard&) = delete;

private:
  struct sigaction old_int_{}, old_term_{};
};

}  // namespace grainflow::scenes
