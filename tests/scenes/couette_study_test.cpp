// The planar Couette measurement (scenes/src/studies/couette.hpp): an exact linear
// profile gives ν exactly; noisy blocks give ν within its stated error about as often as a
// standard error should (≈ 68 %); what cannot be measured is refused; a small scene run
// end to end gives a positive viscosity from a profile that rises from wall to wall.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/core/rng.hpp"
#include "scenes/src/run/scene_catalog.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/studies/couette.hpp"

using namespace grainflow::scenes;
using namespace grainflow::scenes::studies;

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

TEST(CouetteStudy, ASmallChannelRunEndToEnd) {
  const std::string text = R"([run]
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
)";
  const Scene sc = parse_scene(text, "couette.toml");
  CouetteRun run;
  run.skip = 300.0;
  run.progress = false;
  const CouetteInput in = measure_couette(sc, run);
  ASSERT_EQ(in.blocks.size(), 6u);
  ASSERT_EQ(in.y.size(), 8u);
  const CouetteResult r = analyse_couette(in);
  EXPECT_GT(r.nu.value, 0.1);
  EXPECT_LT(r.nu.value, 3.0);
  EXPECT_GT(r.nu.error, 0.0);
  EXPECT_LT(r.profile.front(), -0.05);
  EXPECT_GT(r.profile.back(), 0.05);
  EXPECT_GT(r.stress_low.value, 0.0);
  EXPECT_GT(r.stress_high.value, 0.0);
  EXPECT_NEAR(r.density.value, 0.5 / (3.14159265 / 4), 0.1);
  // Without walls in y there is nothing to measure.
  const Scene box = parse_scene("[run]\nengine = \"ed\"\nuntil = 10.0\n[system]\narea_fraction = 0.3\nbox = [20.0, 20.0]\n");
  EXPECT_THROW(measure_couette(box, run), grainflow::Error);
}
