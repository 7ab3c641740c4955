#include "scenes/src/run/interrupt.hpp"

#include <unistd.h>

namespace grainflow::scenes {

namespace {

std::atomic<bool> g_stop{false};
std::atomic<int> g_signal{0};
static_assert(std::atomic<bool>::is_always_lock_free, "the stop flag is set from a signal handler");
static_assert(std::atomic<int>::is_always_lock_free, "the stop signal is set from a signal handler");

extern "C" void on_stop_signal(int sig) {
  g_signal.store(sig, std::memory_order_relaxed);
  g_stop.store(true, std::memory_order_relaxed);
  // write(2) is async-signal-safe; stdio is not.
  static const char msg[] = "\ngrainflow: stopping, finishing the output written so far (again to abort)\n";
  [[maybe_unused]] const auto n = ::write(STDERR_FILENO, msg, sizeof msg - 1);
}

}  // namespace

const std::atomic<bool>& stop_flag() noexcept { return g_stop; }
int stop_signal() noexcept { return g_signal.load(std::memory_order_relaxed); }
void clear_stop() noexcept {
  g_stop.store(false);
  g_signal.store(0);
}

InterruptGuard::InterruptGuard() {
  struct sigaction sa {};
  sa.sa_handler = &on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND | SA_RESTART;
  sigaction(SIGINT, &sa, &old_int_);
  sigaction(SIGTERM, &sa, &old_term_);
}

InterruptGuard::~InterruptGuard() {
  sigaction(SIGINT, &old_int_, nullptr);
  sigaction(SIGTERM, &old_term_, nullptr);
}

}  // namespace grainflow::scenes
