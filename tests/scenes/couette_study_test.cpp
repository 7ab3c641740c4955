// The planar Couette measurement (scenes/src/studies/couette.hpp) and its study
// ([study] kind = "couette"): an exact linear profile gives ν exactly; noisy blocks give ν
// within its stated error about as often as a standard error should (≈ 68 %); what cannot
// be measured is refused; a small scene run end to end writes a viscosity in a loose band.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/core/rng.hpp"
#include "scenes/src/run/run_loop.hpp"
#include "scenes/src/run/scene_catalog.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/scene/scene_error.hpp"
#include "scenes/src/studies/couette.hpp"
#include "tests/scenes/study_csv.hpp"

using namespace grainflow::scenes;
namespace fs = std::filesystem;

namespace {

// 16 bins over Ly = 64, the bulk their middle half; u = g (y − 32) + noise; σ = ρ ν g.
CouetteInput synthetic(std::size_t blocks, double nu, double g, double noise_u, double noise_s,
                       grainflow::core::Rng* rng) {
  CouetteInput in;
  for (int j = 0; j < 16; ++j) in.y.push_back(2.0 + 4.0 * j);
  in.bulk_lo = 16.0;
  in.bulk_hi = 48.0;
  in.mass = 2.0;
  const double n = 0.8, rho = in.mass * n, stress = rho * nu * g;
  for (std::size_t k = 0; k < blocks; ++k) {
    CouetteBlock b;
    for (double y : in.y) {
      b.ux.push_back(g * (y - 32.0) + (rng ? noise_u * rng->normal() : 0.0));
      b.density.push_back(n);
    }
    const double s = stress + (rng ? noise_s * rng->normal() : 0.0);
    b.fx_low = -s;
    b.fx_high = s;
    b.kT = 0.02;
    in.blocks.push_back(b);
  }
  return in;
}

}  // namespace

TEST(CouetteStudy, ExactProfileGivesTheViscosityExactly) {
  const CouetteResult r = analyse_couette(synthetic(4, 0.65, 1e-3, 0.0, 0.0, nullptr));
  EXPECT_NEAR(r.nu.value, 0.65, 1e-12);
  EXPECT_NEAR(r.nu.error, 0.0, 1e-12);
  EXPECT_NEAR(r.gradient.value, 1e-3, 1e-15);
  EXPECT_NEAR(r.density.value, 1.6, 1e-15);
  EXPECT_NEAR(r.eta.value, 1.6 * 0.65, 1e-12);
  EXPECT_EQ(r.bulk_bins, 8u);
  EXPECT_EQ(r.blocks, 4u);
}

TEST(CouetteStudy, TheErrorIsAStandardError) {
  grainflow::core::Rng rng(5);
  const double truth = 0.65;
  int within = 0;
  double sum = 0.0;
  const int replicas = 400;
  for (int k = 0; k < replicas; ++k) {
    // Per block: the slope's noise ≈ 19 % (5e-3 per bin over 8 bins 4 apart), the stress's
    // 25 %; over 30 blocks ≈ 3.5 % and 4.6 %.
    const CouetteResult r = analyse_couette(synthetic(30, truth, 1e-3, 5e-3, 0.25 * 1.6 * truth * 1e-3, &rng));
    sum += r.nu.value;
    if (std::abs(r.nu.value - truth) < r.nu.error) ++within;
  }
  EXPECT_NEAR(sum / replicas, truth, 0.01 * truth);
  const double fraction = double(within) / replicas;
  EXPECT_GT(fraction, 0.60) << fraction;
  EXPECT_LT(fraction, 0.76) << fraction;
}

TEST(CouetteStudy, RefusesWhatCannotBeMeasured) {
  EXPECT_THROW(analyse_couette(synthetic(1, 0.65, 1e-3, 0.0, 0.0, nullptr)), grainflow::Error);
  CouetteInput narrow = synthetic(4, 0.65, 1e-3, 0.0, 0.0, nullptr);
  narrow.bulk_lo = narrow.bulk_hi = 30.0;
  EXPECT_THROW(analyse_couette(narrow), grainflow::Error);
  CouetteInput empty = synthetic(4, 0.65, 1e-3, 0.0, 0.0, nullptr);
  empty.blocks[2].ux[7] = std::nan("");
  EXPECT_THROW(analyse_couette(empty), grainflow::Error);
  CouetteInput resting = synthetic(4, 0.65, 0.0, 0.0, 0.0, nullptr);
  EXPECT_THROW(analyse_couette(resting), grainflow::Error);
}

// A small channel run end to end as a [study] kind = "couette" scene: study.csv gives a
// positive viscosity in a loose band around the seed's (short, small, sheared hard:
// U = ∓0.2 over 24 σ), both walls' stresses positive and equal within errors, and the
// bulk density of the scene's area fraction; study.png is the profile.
TEST(CouetteStudy, ASmallChannelRunEndToEnd) {
  const fs::path dir = fs::path(GRAINFLOW_TEST_OUT) / "couette_study" / "small";
  fs::remove_all(dir);
  const Scene sc = parse_scene(R"([run]
engine = "ed"
until = 900.0
seed = 2
[system]
box = [24.0, 24.0]
area_fraction = 0.5
kT = 0.02
[boundary]
periodic = [true, false]
[boundary.walls]
kind = "noslip_thermal"
U = [-0.2, 0.2]
[sample]
exposure = 100.0
bins = [2, 8]
[output]
png = false
mp4 = false
stats_every = 50.0
[study]
kind = "couette"
skip = 300.0
)",
                               "couette.toml");
  RunOptions opt;
  opt.dir = dir;
  opt.name = "couette";
  opt.quiet = true;
  ASSERT_EQ(run_scene(sc, opt), 0);
  auto v = grainflow::scenes::test::study_csv_values(dir / "study.csv");
  std::printf("small channel: nu = %.4f ± %.4f, stress = %.4g ± %.2g, du/dy = %.4g ± %.2g\n", v["nu"], v["nu_err"],
              v["stress"], v["stress_err"], v["gradient"], v["gradient_err"]);
  EXPECT_EQ(v["blocks"], 6.0);  // exposures [300, 400] … [800, 900]
  EXPECT_EQ(v["bulk_bins"], 4.0);
  EXPECT_GT(v["nu"], 0.2);
  EXPECT_LT(v["nu"], 2.0);
  EXPECT_GT(v["nu_err"], 0.0);
  EXPECT_LT(v["nu_err"], 0.5 * v["nu"]);
  EXPECT_GT(v["gradient"], 0.0);
  EXPECT_GT(v["stress_low"], 0.0);
  EXPECT_GT(v["stress_high"], 0.0);
  EXPECT_NEAR(v["density"], 0.5 / (std::numbers::pi / 4), 0.1);
  EXPECT_EQ(v["U_high"], 0.2);
  EXPECT_TRUE(fs::exists(dir / "study.png"));
  const std::string json = [&] {
    std::ifstream in(dir / "study.json");
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }();
  EXPECT_NE(json.find("\"study\": \"couette\""), std::string::npos) << json;
}

TEST(CouetteStudy, SceneChecks) {
  auto refused = [](const std::string& text) {
    try {
      parse_scene(text, "couette.toml", {});
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string base = "[run]\nengine = \"ed\"\nuntil = 1000.0\n[system]\nbox = [20.0, 20.0]\narea_fraction = 0.5\n"
                           "[sample]\nexposure = 100.0\n";
  const std::string walls = "[boundary]\nperiodic = [true, false]\n[boundary.walls]\nkind = \"noslip_thermal\"\n"
                            "U = [-0.1, 0.1]\n";
  const std::string study = "[study]\nkind = \"couette\"\nskip = 200.0\n";
  EXPECT_EQ(refused(base + walls + study), "");
  EXPECT_NE(refused(base + study).find("walls in y, periodic in x"), std::string::npos);
  EXPECT_NE(refused(base + "[boundary]\nperiodic = [true, false]\n" + study).find("moving at different speeds"),
            std::string::npos);
  EXPECT_NE(refused(base + walls + study + "[output]\nstats_every = 30.0\n").find("output.stats_every"),
            std::string::npos);
  EXPECT_EQ(refused(base + walls + study + "[output]\nstats_every = 25.0\n"), "");
  EXPECT_NE(refused(base + walls + "[study]\nkind = \"couette\"\nskip = 900.0\n").find("fewer than 2 exposures"),
            std::string::npos);
  EXPECT_NE(refused(base + walls + study + "early = 0.1\n").find("haff_cooling study"), std::string::npos);
  EXPECT_NE(refused(base + walls + "[study]\nkind = \"drag\"\nskip = 100.0\n").find("couette study"), std::string::npos);
}
