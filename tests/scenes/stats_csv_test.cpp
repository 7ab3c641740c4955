// stats.csv: header and rows, .partial until finished, and the Ctrl-C path: a SIGINT sets
// the stop flag, the loop finalises stats.csv and marks run.json "interrupted".
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "engine/core/error.hpp"
#include "scenes/src/run/interrupt.hpp"
#include "scenes/src/outputs/run_record.hpp"
#include "scenes/src/outputs/stats_csv.hpp"

using namespace grainflow::scenes;
namespace fs = std::filesystem;

namespace {

fs::path fresh(const std::string& name) {
  const fs::path d = fs::path(GRAINFLOW_TEST_OUT) / "stats" / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

}  // namespace

TEST(StatsCsv, PartialUntilFinishedThenRenamed) {
  const fs::path d = fresh("rename");
  {
    StatsCsv csv(d / "stats.csv", {"energy", "collisions"});
    csv.row(0.0, {1.0, 2.0});
    csv.row(0.5, {0.1, std::numeric_limits<double>::quiet_NaN()});
    csv.flush();
    EXPECT_TRUE(fs::exists(d / "stats.csv.partial"));
    EXPECT_FALSE(fs::exists(d / "stats.csv"));
    EXPECT_EQ(slurp(d / "stats.csv.partial"), "time,energy,collisions\n0,1,2\n0.5,0.1,nan\n");
    csv.finish();
    csv.finish();  // idempotent
    EXPECT_EQ(csv.rows(), 2u);
  }
  EXPECT_FALSE(fs::exists(d / "stats.csv.partial"));
  EXPECT_EQ(slurp(d / "stats.csv"), "time,energy,collisions\n0,1,2\n0.5,0.1,nan\n");
}

TEST(StatsCsv, UnfinishedRunLeavesOnlyPartial) {
  const fs::path d = fresh("killed");
  {
    StatsCsv csv(d / "stats.csv", {"T"});
    csv.row(1.0, {0.02});
  }
  EXPECT_FALSE(fs::exists(d / "stats.csv"));
  EXPECT_EQ(slurp(d / "stats.csv.partial"), "time,T\n1,0.02\n");
}

TEST(StatsCsv, ShortestRoundTripNumbers) {
  EXPECT_EQ(csv_number(0.30000000000000004), "0.30000000000000004");
  EXPECT_EQ(csv_number(1e-300), "1e-300");
  EXPECT_EQ(csv_number(-std::numeric_limits<double>::infinity()), "-inf");
}

TEST(StatsCsv, RejectsBadColumnsAndRows) {
  const fs::path d = fresh("bad");
  EXPECT_THROW(StatsCsv(d / "a.csv", {"time"}), grainflow::Error);
  EXPECT_THROW(StatsCsv(d / "a.csv", {"a,b"}), grainflow::Error);
  EXPECT_THROW(StatsCsv(d / "a.csv", {"a", "a"}), grainflow::Error);
  EXPECT_THROW(StatsCsv(d / "a.csv", {""}), grainflow::Error);
  EXPECT_THROW(StatsCsv("/etc/passwd/stats.csv", {"a"}), grainflow::Error);
  StatsCsv csv(d / "b.csv", {"a", "b"});
  EXPECT_THROW(csv.row(0.0, {1.0}), std::logic_error);
  csv.finish();
  EXPECT_THROW(csv.row(0.0, {1.0, 2.0}), std::logic_error);
}

TEST(Interrupt, SigintStopsLoopWhichFinalisesOutput) {
  const fs::path d = fresh("sigint");
  clear_stop();
  RunRecord record;
  record.engine = "ed";
  {
    InterruptGuard guard;
    StatsCsv csv(d / "stats.csv", {"step"});
    int step = 0;
    for (; step < 1000 && !stop_requested(); ++step) {
      csv.row(step * 0.1, {double(step)});
      if (step == 9) std::raise(SIGINT);  // the user presses Ctrl-C
    }
    EXPECT_EQ(step, 10);
    EXPECT_EQ(stop_signal(), SIGINT);
    csv.finish();
    record.status = stop_requested() ? RunStatus::Interrupted : RunStatus::Complete;
    write_run_record(record, d / "run.json");
  }
  clear_stop();
  EXPECT_FALSE(stop_requested());
  EXPECT_TRUE(fs::exists(d / "stats.csv"));
  EXPECT_FALSE(fs::exists(d / "stats.csv.partial"));
  std::istringstream rows(slurp(d / "stats.csv"));
  int lines = 0;
  for (std::string l; std::getline(rows, l);) ++lines;
  EXPECT_EQ(lines, 11);  // header + 10 rows
  EXPECT_NE(slurp(d / "run.json").find("\"status\": \"interrupted\""), std::string::npos);
  // The guard restored the previous (default) disposition.
  struct sigaction now {};
  sigaction(SIGINT, nullptr, &now);
  EXPECT_EQ(now.sa_handler, SIG_DFL);
}

TEST(Interrupt, SigtermToo) {
  clear_stop();
  {
    InterruptGuard guard;
    std::raise(SIGTERM);
    EXPECT_TRUE(stop_requested());
    EXPECT_EQ(stop_signal(), SIGTERM);
  }
  clear_stop();
}
