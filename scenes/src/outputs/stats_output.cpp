// DIR/stats.csv: the engine's stats rows (time first, then its named columns), written
// as stats.csv.partial until the run ends (stats_csv.hpp); and DIR/stats.json, the unit
// and definition of every column, as the code computing it documents it (StatsColumn).
// A sidecar rather than a `#` header: stats.csv stays a plain CSV every reader loads
// (numpy.genfromtxt(names=True), pandas, gnuplot, spreadsheets) without options.
#include <optional>

#include "engine/io/archive.hpp"
#include "engine/io/atomic_file.hpp"
#include "scenes/src/outputs/json_writer.hpp"
#include "scenes/src/outputs/output_table.hpp"
#include "scenes/src/outputs/stats_csv.hpp"

namespace grainflow::scenes {
namespace {

// The `time` column, written by stats.csv itself.
const StatsColumn kTime{"time", "τ (ED) or s (DEM)", "simulated time at the end of the row's stats window"};

std::vector<std::string> names(const std::vector<StatsColumn>& columns) {
  std::vector<std::string> n;
  for (const auto& c : columns) n.push_back(c.name);
  return n;
}

}  // namespace

std::string stats_json(const std::vector<StatsColumn>& columns) {
  JsonWriter w;
  w.begin_object().key("file").value("stats.csv").key("columns").begin_array();
  auto column = [&](const StatsColumn& c) {
    w.begin_object().key("name").value(c.name).key("unit").value(c.unit).key("definition").value(c.definition).end_object();
  };
  column(kTime);
  for (const auto& c : columns) column(c);
  w.end_array().end_object();
  return w.str() + "\n";
}

namespace {

class StatsOutput final : public RunOutput {
public:
  StatsOutput(std::filesystem::path dir, std::vector<StatsColumn> columns)
      : file_(dir / "stats.csv"), json_(dir / "stats.json"), columns_(std::move(columns)) {}
  void start(const RunRecord&) override {
    io::write_text_atomically(json_, stats_json(columns_));
    csv_.emplace(file_, names(columns_));
  }
  void checkpoint(io::ArchiveWriter& w) override {
    w.tag("stats.csv");
    w.pod(csv_->position());
  }
  void resume(io::ArchiveReader& r, const RunRecord&) override {
    r.tag("stats.csv");
    io::write_text_atomically(json_, stats_json(columns_));
    csv_.emplace(file_, names(columns_), r.get<StatsCsv::Position>());
  }
  void stats(double time, std::span<const double> row) override { csv_->row(time, row); }
  void finish(const RunRecord&) override { csv_->finish(); }

private:
  std::filesystem::path file_, json_;
  std::vector<StatsColumn> columns_;
  std::optional<StatsCsv> csv_;
};

void declare(Schema& s) {
  s.table("output")
      .add_float(stats_keys::every, 0.0, "simulated time between stats.csv rows (0 = one per frame)", "time units")
      .at_least(0.0);
}

std::unique_ptr<RunOutput> open(const OutputContext& c) {
  c.claim("stats.csv");
  c.claim("stats.json");
  return std::make_unique<StatsOutput>(c.dir, c.stats_columns);
}

}  // namespace

OutputEntry stats_output() { return {"stats", "stats.csv, one row per stats interval, and stats.json documenting its columns", &declare, nullptr, &open}; }

}  // namespace grainflow::scenes
