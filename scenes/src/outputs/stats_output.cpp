// DIR/stats.csv: the engine's stats rows (time first, then its named columns), written
// as stats.csv.partial until the run ends (stats_csv.hpp).
#include "scenes/src/outputs/output_table.hpp"
#include "scenes/src/outputs/stats_csv.hpp"

namespace grainflow::scenes {
namespace {

class StatsOutput final : public RunOutput {
public:
  StatsOutput(const std::filesystem::path& file, std::vector<std::string> columns) : csv_(file, std::move(columns)) {}
  void stats(double time, std::span<const double> row) override { csv_.row(time, row); }
  void finish(const RunRecord&) override { csv_.finish(); }

private:
  StatsCsv csv_;
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
