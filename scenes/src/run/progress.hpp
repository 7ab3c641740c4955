// Progress of a long run on stderr (ARCHITECTURE.md): on a terminal one line rewritten in
// place (simulated time / target, percent, throughput, ETA); otherwise a plain line every
// few seconds. update() is cheap enough to call every event: it reads the clock only every
// `stride` calls, with the stride adapted so the clock is read about every 20 ms.
#pragma once
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

namespace grainflow::scenes {

// "--" (unknown), "42s", "3m07s", "2h05m", "3d04h".
std::string format_duration(double seconds);
// "950 events/s", "1.23 k steps/s", "4.56 M collisions/s"; unit is the thing counted.
std::string format_rate(double per_second, std::string_view unit);
// Remaining wall seconds to go from `done` to `target`, at the average rate since `done0`
// was reached `elapsed_s` seconds ago; NaN when no progress was made yet.
double eta_seconds(double done0, double done, double target, double elapsed_s);

struct ProgressState {
  std::string_view label = "t";  // what `done` counts: "t" (simulated time), "step"
  double done = 0, target = 0;
  double elapsed_s = 0;          // wall time since the reporter started
  double work_rate = 0;          // work units per wall second
  std::string_view work_unit = "events";
  double eta_s = 0;              // NaN = unknown
};
// "t = 1234.5 / 17760 (7.0%)  1.23 M events/s  ETA 3m07s"
std::string format_progress_line(const ProgressState& s);

class ProgressReporter {
public:
  struct Options {
    double target = 0;
    std::string label = "t";
    std::string work_unit = "events";
    std::FILE* out = stderr;
    int tty = -1;                 // -1: isatty(fileno(out)); 0/1 to force (tests)
    double tty_interval_s = 0.25;
    double plain_interval_s = 5.0;
  };
  explicit ProgressReporter(Options o);

  // `done` in the label's unit, `work` a cumulative count (events, steps, frames).
  void update(double done, double work) {
    if (--countdown_ > 0) return;
    poll(done, work);
  }
  // Prints the final line (ending the \r line on a terminal).
  void finish(double done, double work);

  // Lines written so far (tests, and to know whether anything was shown).
  std::size_t lines_written() const { return lines_; }
  std::int64_t stride() const { return stride_; }

private:
  using Clock = std::chrono::steady_clock;
  void poll(double done, double work);
  void print(double done, double work, Clock::time_point now, bool final);

  Options opt_;
  bool tty_;
  std::int64_t countdown_ = 1, stride_ = 1;
  Clock::time_point start_, last_check_, last_print_;
  bool have_base_ = false;
  double done0_ = 0, work0_ = 0;
  std::size_t lines_ = 0;
  std::size_t last_len_ = 0;
};

}  // namespace grainflow::scenes
