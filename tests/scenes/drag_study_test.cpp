// The drag study (scenes/src/studies/drag.cpp, seed 003 Fig. 4.19) and its error bars,
// block_average() (study.hpp): on AR(1) series, whose variance of the mean is known
// exactly, the error is a standard error (its rms matches the true one, ±1 error holds the
// truth ≈ 68 % of the time) where the rows' own scatter is 4× too small; a short series
// says its blocks are too short; a small stream past an obstacle writes its drag / D.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/core/rng.hpp"
#include "scenes/src/run/run_loop.hpp"
#include "scenes/src/run/scene_catalog.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/scene/scene_error.hpp"
#include "scenes/src/studies/study.hpp"
#include "tests/scenes/study_csv.hpp"

namespace fs = std::filesystem;
using namespace grainflow::scenes;

namespace {

// x_i = φ x_{i−1} + ε_i, ε ~ N(0, 1), started in the stationary state (variance 1/(1 − φ²)).
std::vector<double> ar1(double phi, std::size_t n, double mean, grainflow::core::Rng& rng) {
  std::vector<double> x(n);
  double v = rng.normal() / std::sqrt(1 - phi * phi);
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0) v = phi * v + rng.normal();
    x[i] = mean + v;
  }
  return x;
}

// The exact variance of the mean of n stationary AR(1) values.
double ar1_variance_of_mean(double phi, double n) {
  const double var = 1 / (1 - phi * phi);
  return var / n * ((1 + phi) / (1 - phi) - 2 * phi * (1 - std::pow(phi, n)) / (n * (1 - phi) * (1 - phi)));
}

}  // namespace

TEST(BlockAverage, Ar1ErrorIsTheStandardErrorOfTheMean) {
  grainflow::core::Rng rng(11);
  const double phi = 0.9, truth = 3.0;
  const std::size_t n = 16384;
  const double sd = std::sqrt(ar1_variance_of_mean(phi, double(n)));  // ≈ 0.034
  const int replicas = 300;
  double sum_err2 = 0, sum_tau = 0, sum_naive2 = 0;
  int within = 0, enough = 0;
  for (int k = 0; k < replicas; ++k) {
    const auto x = ar1(phi, n, truth, rng);
    const BlockAverage a = block_average(x);
    sum_err2 += a.error * a.error;
    sum_tau += a.tau_int;
    enough += a.long_enough ? 1 : 0;
    if (std::abs(a.mean - truth) < a.error) ++within;
    const MeanError rows = block_mean(x, int(n));  // every row a block: the scatter of the rows
    sum_naive2 += rows.error * rows.error;
  }
  const double rms = std::sqrt(sum_err2 / replicas), naive = std::sqrt(sum_naive2 / replicas);
  const double tau = sum_tau / replicas, fraction = double(within) / replicas;
  std::printf("AR(1) φ = 0.9, n = %zu: true sd of the mean %.4f, block error rms %.4f (%.3f), rows' scatter %.4f; "
              "τ_int %.2f (exact 9.5); within ±1 error %.3f\n",
              n, sd, rms, rms / sd, naive, tau, fraction);
  EXPECT_EQ(enough, replicas);
  EXPECT_NEAR(tau, (1 + phi) / (2 * (1 - phi)), 0.1 * 9.5);
  EXPECT_NEAR(rms / sd, 1.0, 0.08);
  EXPECT_LT(naive / sd, 0.3);  // independent rows would claim a 4× smaller error
  EXPECT_GT(fraction, 0.60);
  EXPECT_LT(fraction, 0.76);
}

TEST(BlockAverage, WhiteNoiseAndShortSeries) {
  grainflow::core::Rng rng(3);
  const auto white = ar1(0.0, 4000, 0.0, rng);
  const BlockAverage w = block_average(white);
  EXPECT_NEAR(w.tau_int, 0.5, 0.1);
  EXPECT_TRUE(w.long_enough);
  EXPECT_NEAR(w.error, 1 / std::sqrt(4000.0), 0.3 / std::sqrt(4000.0));
  // 400 rows of τ_int ≈ 9.5: 8 blocks would need 8 · 190 rows.
  const BlockAverage s = block_average(ar1(0.9, 400, 0.0, rng));
  EXPECT_FALSE(s.long_enough);
  EXPECT_EQ(s.blocks, 8u);
  EXPECT_EQ(s.block_rows, 50u);
  EXPECT_TRUE(std::isfinite(s.error));
}

// A small dense stream past a no-slip obstacle (obstacle_quick's set-up, shorter): the drag
// along the stream is positive, the lift averages out within a few errors.
TEST(DragStudy, SmallStreamWritesDragPerDiameter) {
  const fs::path dir = fs::path(GRAINFLOW_TEST_OUT) / "drag_study" / "small";
  fs::remove_all(dir);
  const Scene sc = parse_scene(R"([run]
engine = "ed"
until = 160.0
seed = 1
[system]
box = [80.0, 40.0]
area_fraction = 0.65
kT = 0.02
U = 0.2
[boundary]
periodic = [false, true]
[boundary.stream]
kind = "dispenser_filter"
filter_distance = 3.0
[boundary.obstacle]
D = 10.0
x = 25.0
y = 20.0
kind = "noslip_thermal"
[sample]
exposure = 20.0
bins = [8, 4]
[output]
png = false
mp4 = false
stats_every = 0.5
[study]
kind = "drag"
transient = 40.0
)",
                               "drag.toml");
  RunOptions opt;
  opt.dir = dir;
  opt.name = "drag";
  opt.quiet = true;
  ASSERT_EQ(run_scene(sc, opt), 0);
  auto v = grainflow::scenes::test::study_csv_values(dir / "study.csv");
  std::printf("small stream U = 0.2, D = 10: drag/D = %.4g ± %.2g, lift/D = %.3g ± %.2g, τ_int = %.3g, %g blocks\n",
              v["drag_per_D"], v["drag_per_D_err"], v["lift_per_D"], v["lift_per_D_err"], v["tau_int"], v["blocks"]);
  EXPECT_EQ(v["U"], 0.2);
  EXPECT_EQ(v["D"], 10.0);
  EXPECT_EQ(v["obstacle_kind"], 1.0);
  EXPECT_GT(v["drag_per_D"], 3 * v["drag_per_D_err"]);
  EXPECT_GT(v["drag_per_D_err"], 0.0);
  EXPECT_LT(std::abs(v["lift_per_D"]), 4 * v["lift_per_D_err"] + 0.2 * v["drag_per_D"]);
  EXPECT_EQ(v["measured_span"], 120.0);
  EXPECT_TRUE(fs::exists(dir / "study.png"));
}

TEST(DragStudy, SceneChecks) {
  auto refused = [](const std::string& text) {
    try {
      parse_scene(text, "drag.toml", {});
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string base = "[run]\nengine = \"ed\"\nuntil = 100.0\n[system]\nbox = [40.0, 20.0]\narea_fraction = 0.5\n";
  const std::string stream = "U = 0.1\n[boundary]\nperiodic = [false, true]\n[boundary.stream]\nkind = "
                             "\"dispenser_filter\"\n";
  const std::string obstacle = "[boundary.obstacle]\nD = 4.0\nx = 10.0\ny = 10.0\n";
  const std::string study = "[study]\nkind = \"drag\"\n";
  EXPECT_EQ(refused(base + stream + obstacle + study + "transient = 10.0\n"), "");
  EXPECT_NE(refused(base + stream + study).find("with [boundary.obstacle]"), std::string::npos);
  EXPECT_NE(refused(base + obstacle + study).find("system.U > 0"), std::string::npos);
  EXPECT_NE(refused(base + stream + obstacle + "[study]\nkind = \"couette\"\ntransient = 1.0\n").find("drag study"),
            std::string::npos);
}
