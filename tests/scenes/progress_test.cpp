// Progress reporter: pure formatting of durations, rates, ETA and the line; terminal vs
// plain output; the adaptive clock stride that makes per-event calls cheap.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "scenes/src/run/progress.hpp"

using namespace grainflow::scenes;

namespace {

std::string read_all(std::FILE* f) {
  std::fflush(f);
  std::rewind(f);
  std::string s;
  char buf[512];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) s.append(buf, n);
  return s;
}

}  // namespace

TEST(Progress, FormatDuration) {
  EXPECT_EQ(format_duration(0), "0s");
  EXPECT_EQ(format_duration(59.9), "59s");
  EXPECT_EQ(format_duration(60), "1m00s");
  EXPECT_EQ(format_duration(187), "3m07s");
  EXPECT_EQ(format_duration(3600), "1h00m");
  EXPECT_EQ(format_duration(7500), "2h05m");
  EXPECT_EQ(format_duration(86400 + 4 * 3600 + 59), "1d04h");
  EXPECT_EQ(format_duration(std::nan("")), "--");
  EXPECT_EQ(format_duration(INFINITY), "--");
  EXPECT_EQ(format_duration(-1), "--");
}

TEST(Progress, FormatRate) {
  EXPECT_EQ(format_rate(950, "events"), "950 events/s");
  EXPECT_EQ(format_rate(2.5, "frames"), "2.5 frames/s");
  EXPECT_EQ(format_rate(1234, "steps"), "1.23 k steps/s");
  EXPECT_EQ(format_rate(4.56e6, "collisions"), "4.56 M collisions/s");
  EXPECT_EQ(format_rate(1.5e9, "events"), "1.5 G events/s");
  EXPECT_EQ(format_rate(std::nan(""), "events"), "-- events/s");
}

TEST(Progress, EtaFromAverageRate) {
  // 25 units in 10 s, 75 to go: 30 s.
  EXPECT_DOUBLE_EQ(eta_seconds(0, 25, 100, 10), 30.0);
  // A resumed run counts from where it started.
  EXPECT_DOUBLE_EQ(eta_seconds(50, 60, 100, 5), 20.0);
  EXPECT_DOUBLE_EQ(eta_seconds(0, 120, 100, 5), 0.0);
  EXPECT_TRUE(std::isnan(eta_seconds(10, 10, 100, 5)));
  EXPECT_TRUE(std::isnan(eta_seconds(0, 10, 100, 0)));
}

TEST(Progress, LineFormat) {
  ProgressState s;
  s.label = "t";
  s.done = 1234.5;
  s.target = 17760;
  s.elapsed_s = 65;
  s.work_rate = 1.234e6;
  s.work_unit = "events";
  s.eta_s = 187;
  EXPECT_EQ(format_progress_line(s), "t = 1234.5 / 17760 (7.0%)  1.23 M events/s  elapsed 1m05s  ETA 3m07s");
  s.label = "step";
  s.done = 5000;
  s.target = 10000;
  s.work_unit = "steps";
  s.work_rate = 800;
  s.eta_s = std::nan("");
  EXPECT_EQ(format_progress_line(s), "step = 5000 / 10000 (50.0%)  800 steps/s  elapsed 1m05s  ETA --");
}

TEST(Progress, PlainOutputIsOneLinePerReport) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  ProgressReporter::Options o;
  o.target = 100;
  o.out = f;
  o.tty = 0;
  o.plain_interval_s = 0;  // report at every clock check
  ProgressReporter p(o);
  for (int i = 1; i <= 3; ++i) p.update(10.0 * i, 1000.0 * i);
  p.finish(100, 10000);
  const std::string s = read_all(f);
  std::fclose(f);
  EXPECT_EQ(s.find('\r'), std::string::npos);
  EXPECT_GE(p.lines_written(), 2u);
  EXPECT_NE(s.find("t = 100 / 100 (100.0%)"), std::string::npos) << s;
  EXPECT_NE(s.find("ETA 0s\n"), std::string::npos) << s;
  EXPECT_EQ(s.back(), '\n');
}

TEST(Progress, TerminalOutputRewritesOneLine) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  ProgressReporter::Options o;
  o.target = 10;
  o.label = "step";
  o.work_unit = "steps";
  o.out = f;
  o.tty = 1;
  o.tty_interval_s = 0;
  ProgressReporter p(o);
  p.update(1, 1);
  p.update(2, 2);
  p.finish(10, 10);
  const std::string s = read_all(f);
  std::fclose(f);
  EXPECT_EQ(s.front(), '\r');
  EXPECT_EQ(std::count(s.begin(), s.end(), '\n'), 1);  // only the final line ends
  EXPECT_EQ(s.back(), '\n');
  EXPECT_NE(s.find("\rstep = 10 / 10 (100.0%)"), std::string::npos) << s;
}

TEST(Progress, StrideGrowsSoPerEventCallsAreCheap) {
  std::FILE* f = std::tmpfile();
  ProgressReporter::Options o;
  o.target = 1e9;
  o.out = f;
  o.tty = 0;
  o.plain_interval_s = 1e9;  // never print
  ProgressReporter p(o);
  const int n = 20'000'000;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < n; ++i) p.update(double(i), double(i));
  const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count() / n;
  std::fclose(f);
  EXPECT_GT(p.stride(), 64);  // the clock is read far less often than once per call
  EXPECT_EQ(p.lines_written(), 0u);
  std::printf("ProgressReporter::update: %.2f ns per call, stride %lld\n", ns, static_cast<long long>(p.stride()));
}
