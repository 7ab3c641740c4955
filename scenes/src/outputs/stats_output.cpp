// DIR/stats.csv: the engine's stats rows (time first, then its named columns), written
// as stats.csv.partial until the run ends (stats_csv.hpp).
#include <optional>

#include "engine/io/archive.hpp"
#include "scenes/src/outputs/output_table.hpp"
#include "scenes/src/outputs/stats_csv.hpp"

namespace grainflow::scenes {
namespace {

class StatsOutput final : public RunOutput {
public:
  StatsOutput(std::filesystem::path file, std::vector<std::string> columns)
      : file_(std::move(file)), columns_(std::move(columns)) {}
  void start(const RunRecord&) override { csv_.emplace(file_, columns_); }
  void checkpoint(io::ArchiveWriter& w) override {
    w.tag("stats.csv");
    w.pod(csv_->position());
  }
  void resume(io::ArchiveReader& r, const RunRecord&) override {
    r.tag("stats.csv");
    csv_.emplace(file_, columns_, r.get<StatsCsv::Position>());
  }
  void stats(double time, std::span<const double> row) override { csv_->row(time, row); }
  void finish(const RunRecord&) override { csv_->finish(); }

private:
  std::filesystem::path file_;
  std::vector<std::string> columns_;
  std::optional<StatsCsv> csv_;
};

void declare(Schema& s) {
  s.table("output")
      .add_float(stats_keys::every, 0.0, "simulated time between stats.csv rows (0 = one per frame)", "time units")
      .at_least(0.0);
}

std::unique_ptr<RunOutput> open(const OutputContext& c) {
  c.claim("stats.csv");
  return std::make_unique<StatsOutput>(c.dir / "stats.csv", c.stats_columns);
}

}  // namespace

OutputEntry stats_output() { return {"stats", "stats.csv, one row per stats interval", &declare, nullptr, &open}; }

}  // namespace grainflow::scenes
