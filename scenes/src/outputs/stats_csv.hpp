// stats.csv (SPEC.md §3b): one row per sample, `time` first, then named columns. Written
// to stats.csv.partial, flushed regularly, renamed to stats.csv by finish() (on completion
// and after Ctrl-C), so a killed run leaves only a .partial, never a finished-looking file.
#pragma once
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "engine/io/partial_file.hpp"
#include "scenes/src/outputs/run_output.hpp"
#include "scenes/src/scene/schema.hpp"

namespace grainflow::scenes {

// stats.json: every column of stats.csv (time first) with its unit and definition.
std::string stats_json(const std::vector<StatsColumn>& columns);

namespace stats_keys {
// Simulated time between rows (0 = one per frame): the run loop schedules rows by it.
inline constexpr Key<double> every{"output.stats_every"};
}  // namespace stats_keys

class StatsCsv {
public:
  // `final_path` is DIR/stats.csv; rows go to DIR/stats.csv.partial until finish().
  // Column names must be non-empty, unique, not "time", without , " or newlines
  // (grainflow::Error otherwise, as for an unwritable path).
  StatsCsv(std::filesystem::path final_path, std::vector<std::string> columns, double flush_interval_s = 1.0);
  // Where a checkpoint left the file: its size after a flush and the rows in it.
  struct Position {
    std::uint64_t bytes = 0;
    std::uint64_t rows = 0;
  };
  // Continues the file of a checkpointed run from `at` (io::PartialFile::resume).
  StatsCsv(std::filesystem::path final_path, std::vector<std::string> columns, Position at,
           double flush_interval_s = 1.0);
  ~StatsCsv() = default;  // leaves the .partial file when finish() was not called
  StatsCsv(const StatsCsv&) = delete;
  StatsCsv& operator=(const StatsCsv&) = delete;

  // One sample; values.size() must equal the number of columns.
  void row(double time, std::span<const double> values);
  void row(double time, std::initializer_list<double> values) { row(time, std::span<const double>(values.begin(), values.size())); }
  void flush();
  // Flushes and says where the file stands (for a checkpoint).
  Position position();
  // Flushes, closes and renames .partial to the final name. Idempotent.
  void finish();

  const std::filesystem::path& final_path() const { return file_.final_path(); }
  const std::filesystem::path& partial_path() const { return file_.partial_path(); }
  const std::vector<std::string>& columns() const { return columns_; }
  std::size_t rows() const { return rows_; }
  bool finished() const { return file_.finished(); }

private:
  static void check_columns(const std::vector<std::string>& columns);
  std::vector<std::string> columns_;
  io::PartialFile file_;
  std::size_t rows_ = 0;
  std::chrono::steady_clock::duration flush_interval_;
  std::chrono::steady_clock::time_point last_flush_;
  std::string line_;
};

// A CSV field for a double: shortest round-trip text; "nan", "inf", "-inf" for non-finite.
std::string csv_number(double v);

}  // namespace grainflow::scenes
