// The DEM stats rows as the runner writes them: the pressure tensor is the mean of its
// samples, one at the end of every advance, since the previous row (the other columns
// are the state at the row's time).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "engine/dem/simulation.hpp"
#include "scenes/src/engines/engine_runner.hpp"
#include "scenes/src/engines/engine_table.hpp"
#include "scenes/src/run/scene_catalog.hpp"
#include "scenes/src/scene/scene.hpp"

namespace grainflow::scenes {
namespace {

// 500 spheres falling into a closed box and piling up on its floor.
Scene falling_bed() {
  return parse_scene(R"([run]
engine = "dem"
until = 0.06
[system]
box = [0.008, 0.008, 0.03]
gravity = [0.0, 0.0, -9.81]
[system.contact]
normal = "walton"
tangential = "walton"
kn = 100.0
kt = 80.0
e = 0.9
mu = 0.5
[[system.group]]
N = 500
radius = 0.5e-3
density = 2500.0
[system.initial]
kind = "lattice"
[sample]
exposure = 0.06
)");
}

TEST(DemStatsWindow, PressureRowIsTheMeanOfItsSamplesSinceThePreviousRow) {
  // One thread: on a loaded machine spinning OpenMP waits would stretch the run.
  const int threads = dem::thread_count();
  dem::set_thread_count(1);
  const Scene sc = falling_bed();
  auto every = find_engine("dem")->make_runner(sc), window = find_engine("dem")->make_runner(sc);
  const auto columns = every->stats_columns();
  auto column = [&](const std::string& name) {
    const auto it = std::find_if(columns.begin(), columns.end(), [&](const StatsColumn& c) { return c.name == name; });
    EXPECT_NE(it, columns.end()) << name;
    return std::size_t(it - columns.begin());
  };
  const std::vector<std::string> tensor = {"P_xx", "P_yy", "P_zz", "P_xy", "P_xz", "P_yz"};
  // `every` writes a row after each advance (a window of one sample: the state then),
  // `window` one row after all of them: the same trajectory, so its row is their mean.
  const int k = 6;
  std::vector<std::vector<double>> rows;
  for (int s = 1; s <= k; ++s) {
    const double t = 0.01 * s;
    every->advance_to(t);
    window->advance_to(t);
    rows.push_back(every->stats_row());
  }
  const std::vector<double> row = window->stats_row();
  ASSERT_EQ(row.size(), columns.size());
  EXPECT_EQ(row[column("step")], rows.back()[column("step")]);
  EXPECT_EQ(row[column("kinetic_energy")], rows.back()[column("kinetic_energy")]);  // not a window
  EXPECT_GT(rows.back()[column("contacts")], 100.0);
  for (const std::string& name : tensor) {
    const std::size_t c = column(name);
    double sum = 0.0;
    for (const auto& r : rows) sum += r[c];
    EXPECT_EQ(row[c], sum / k) << name;
  }
  // The samples differ (the bed forms): the window is not just the last one.
  EXPECT_NE(row[column("P_zz")], rows.back()[column("P_zz")]);
  const double trace = (row[column("P_xx")] + row[column("P_yy")] + row[column("P_zz")]) / 3.0;
  EXPECT_DOUBLE_EQ(row[column("pressure")], trace);
  // The next row starts a new window: one more advance, one sample.
  every->advance_to(0.07);
  window->advance_to(0.07);
  const std::vector<double> next = window->stats_row(), one = every->stats_row();
  for (const std::string& name : tensor) EXPECT_EQ(next[column(name)], one[column(name)]) << name;
  dem::set_thread_count(threads);
}

}  // namespace
}  // namespace grainflow::scenes
