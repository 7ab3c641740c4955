// Studies (issue 13, item 6): a scene with a [study] section measures something from its
// own run — Haff's cooling law, the thermostat temperature that holds a kT, the speed of
// sound, the Couette viscosity, the drag on the obstacle — and writes the result and a
// plot into its run folder:
//   DIR/study.json  {"study": kind, "run_status": …, "values": {name: {value, error, unit, …}},
//                    "checks": [{name, passed, detail}], "notes": [...]}
//   DIR/study.csv   the values as one CSV row (NAME, NAME_err): a sweep's runs are the rows
//                   of one table (`grainflow plot --rows out/sweep_*/study.csv`)
//   DIR/study.png   the plot (render/plot), drawn with the run's GL context
// A study is a consumer of the run's stats rows (and frames, if it wants fields) that
// decides at the end what they mean. One row per kind in study_table.cpp; to add a study
// see ARCHITECTURE.md, "To add … a study".
#pragma once
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "render/plot/plot.hpp"
#include "render/snapshot.hpp"

namespace grainflow::io {
class ArchiveWriter;
class ArchiveReader;
}  // namespace grainflow::io

namespace grainflow::scenes {

class Scene;
class Schema;

inline constexpr double kNoError = std::numeric_limits<double>::quiet_NaN();

// One measured or derived number. `error`: one standard error (NaN when there is none).
struct StudyValue {
  std::string name;
  double value = 0;
  double error = kNoError;
  std::string unit;
  std::string doc;
};

// An acceptance criterion the study evaluates (the "within 5 %").
struct StudyCheck {
  std::string name;
  bool passed = false;
  std::string detail;
};

struct StudyResult {
  std::vector<StudyValue> values;
  std::vector<StudyCheck> checks;
  std::vector<std::string> notes;  // what the numbers do not say (late-time departures, …)
  render::plot::Figure figure;
};

// What a study is opened with.
struct StudyContext {
  const Scene& scene;
  std::vector<std::string> stats_columns;  // after `time`, as the engine names them
};

class Study {
public:
  virtual ~Study() = default;
  // Every stats row, in time order (`row` as stats_columns name it).
  virtual void stats(double time, std::span<const double> row) = 0;
  // Every frame (fields and particles as drawn), for studies of profiles.
  virtual void frame(std::int64_t /*index*/, const render::Snapshot& /*snapshot*/) {}
  // What the study has gathered, for a checkpoint, and back on --resume.
  virtual void save(io::ArchiveWriter& w) const = 0;
  virtual void load(io::ArchiveReader& r) = 0;
  // At the end of the run (complete or interrupted): the result and its plot. Throws
  // grainflow::Error when the run gave it too little to say anything.
  virtual StudyResult result() const = 0;
};

struct StudyEntry {
  std::string_view name;
  std::string_view description;
  std::string_view engine;  // the engine whose stats it reads ("ed")
  // Declares its study.* keys (read only when this kind is chosen) and cross-key checks.
  void (*declare_keys)(Schema&);
  std::unique_ptr<Study> (*open)(const StudyContext&);
};

// The stats rows a study keeps: time and the columns it asked for, saved in checkpoints.
class StatsRows {
public:
  // Throws grainflow::Error naming the study and the column when the run has no such
  // column (the study needs an agent the scene does not attach).
  StatsRows(std::string_view study, const std::vector<std::string>& columns, std::vector<std::string> wanted);
  void add(double time, std::span<const double> row);
  std::size_t size() const { return time_.size(); }
  const std::vector<double>& time() const { return time_; }
  // The column by the name it was asked for.
  const std::vector<double>& column(std::string_view name) const;
  // The first row after `start` (the transient a study leaves out). Throws grainflow::Error
  // naming the study, `key` (what set start) and `remedy` when fewer than `need` rows follow.
  std::size_t first_row_after(double start, std::size_t need, std::string_view key, std::string_view remedy) const;
  void save(io::ArchiveWriter& w) const;
  void load(io::ArchiveReader& r);

private:
  std::string study_;
  std::vector<std::string> wanted_;
  std::vector<std::size_t> index_;
  std::vector<double> time_;
  std::vector<std::vector<double>> values_;
};

// Mean and standard error of the mean of `x` by block averaging: the series is cut into
// `blocks` equal blocks (the last rows dropped), the error is the blocks' standard
// deviation / √blocks — honest for correlated samples when a block is longer than the
// correlation time. NaN error for fewer than 2 blocks' worth.
struct MeanError {
  double mean = 0, error = kNoError;
};
MeanError block_mean(std::span<const double> x, int blocks = 8);

// Block averaging with the block length chosen from the series itself (the drag study,
// seed 003 Fig. 4.19). The rule: τ_int = 1/2 + Σ_{k=1..M} ρ_k, the integrated
// autocorrelation time in rows, with Sokal's window (the smallest M ≥ 5 τ_int(M)); blocks
// of L = ⌈20 τ_int⌉ rows, so that the block means are nearly independent (for an AR(1)
// series the variance of an L-row block mean falls short of its long-block value by
// ≈ τ_int/L: 5 % in the variance, 2.5 % in the error); error = the block means' standard
// deviation / √blocks. With fewer than `min_blocks` such blocks the series is cut into
// `min_blocks` shorter ones and `long_enough` is false: the error is then likely low.
struct BlockAverage {
  double mean = 0, error = kNoError;
  double tau_int = 0;         // rows
  std::size_t block_rows = 0, blocks = 0;
  bool long_enough = false;   // blocks of at least 20 τ_int rows
};
BlockAverage block_average(std::span<const double> x, int min_blocks = 8);

}  // namespace grainflow::scenes
