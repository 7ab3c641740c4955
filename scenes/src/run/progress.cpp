#include "scenes/src/run/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace grainflow::scenes {

std::string format_duration(double s) {
  if (!std::isfinite(s) || s < 0) return "--";
  char buf[48];
  if (s < 60) {
    std::snprintf(buf, sizeof buf, "%.0fs", std::floor(s));
    return buf;
  }
  const auto total = static_cast<long long>(std::llround(s));
  const long long d = total / 86400, h = total % 86400 / 3600, m = total % 3600 / 60, sec = total % 60;
  if (total < 3600)
    std::snprintf(buf, sizeof buf, "%lldm%02llds", m, sec);
  else if (total < 86400)
    std::snprintf(buf, sizeof buf, "%lldh%02lldm", h, m);
  else
    std::snprintf(buf, sizeof buf, "%lldd%02lldh", d, h);
  return buf;
}

std::string format_rate(double r, std::string_view unit) {
  char buf[64];
  const char* prefix = "";
  double v = r;
  if (!std::isfinite(r) || r < 0) return "-- " + std::string(unit) + "/s";
  if (r >= 1e9) v = r / 1e9, prefix = "G ";
  else if (r >= 1e6) v = r / 1e6, prefix = "M ";
  else if (r >= 1e3) v = r / 1e3, prefix = "k ";
  if (*prefix)
    std::snprintf(buf, sizeof buf, "%.3g %s", v, prefix);
  else
    std::snprintf(buf, sizeof buf, v >= 10 ? "%.0f " : "%.2g ", v);
  return buf + std::string(unit) + "/s";
}

double eta_seconds(double done0, double done, double target, double elapsed_s) {
  const double progressed = done - done0;
  if (!(progressed > 0) || !(elapsed_s > 0)) return std::numeric_limits<double>::quiet_NaN();
  return std::max(0.0, target - done) * elapsed_s / progressed;
}

namespace {
std::string amount(double v) {
  char buf[40];
  if (std::abs(v) < 1e15 && v == std::floor(v))
    std::snprintf(buf, sizeof buf, "%.0f", v);
  else
    std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}
}  // namespace

std::string format_progress_line(const ProgressState& s) {
  std::string line = std::string(s.label) + " = " + amount(s.done) + " / " + amount(s.target);
  if (s.target > 0) {
    char pct[32];
    std::snprintf(pct, sizeof pct, " (%.1f%%)", std::clamp(100.0 * s.done / s.target, 0.0, 100.0));
    line += pct;
  }
  line += "  " + format_rate(s.work_rate, s.work_unit);
  line += "  elapsed " + format_duration(s.elapsed_s);
  line += "  ETA " + format_duration(s.eta_s);
  return line;
}

ProgressReporter::ProgressReporter(Options o) : opt_(std::move(o)) {
  tty_ = opt_.tty >= 0 ? opt_.tty != 0 : ::isatty(::fileno(opt_.out)) != 0;
  start_ = last_check_ = last_print_ = Clock::now();
}

void ProgressReporter::poll(double done, double work) {
  const auto now = Clock::now();
  if (!have_base_) {
    // Rates and ETA are measured from the first update (a resumed run starts at done > 0).
    have_base_ = true;
    done0_ = done, work0_ = work;
    start_ = last_print_ = now;
  }
  // Aim at one clock read per ~20 ms whatever one update costs.
  const double since = std::chrono::duration<double>(now - last_check_).count();
  if (since < 0.005 && stride_ < (std::int64_t(1) << 24)) stride_ *= 2;
  else if (since > 0.05 && stride_ > 1) stride_ /= 2;
  last_check_ = now;
  countdown_ = stride_;
  const double interval = tty_ ? opt_.tty_interval_s : opt_.plain_interval_s;
  if (std::chrono::duration<double>(now - last_print_).count() >= interval) print(done, work, now, false);
}

void ProgressReporter::print(double done, double work, Clock::time_point now, bool final) {
  last_print_ = now;
  ProgressState s;
  s.label = opt_.label;
  s.done = done;
  s.target = opt_.target;
  s.elapsed_s = std::chrono::duration<double>(now - start_).count();
  s.work_rate = s.elapsed_s > 0 ? (work - work0_) / s.elapsed_s : 0.0;
  s.work_unit = opt_.work_unit;
  s.eta_s = final ? 0.0 : eta_seconds(done0_, done, opt_.target, s.elapsed_s);
  std::string line = format_progress_line(s);
  if (tty_) {
    // Pad over the remains of a longer previous line instead of relying on escape codes.
    const std::size_t len = line.size();
    if (len < last_len_) line.append(last_len_ - len, ' ');
    last_len_ = len;
    std::fprintf(opt_.out, "\r%s%s", line.c_str(), final ? "\n" : "");
  } else {
    std::fprintf(opt_.out, "%s\n", line.c_str());
  }
  std::fflush(opt_.out);
  ++lines_;
}

void ProgressReporter::finish(double done, double work) {
  if (!have_base_) {
    have_base_ = true;
    done0_ = done, work0_ = work;
  }
  print(done, work, Clock::now(), true);
}

}  // namespace grainflow::scenes
