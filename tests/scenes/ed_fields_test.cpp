// The fields an ED run draws, as the runner hands them to the renderer: bins an obstacle
// covers in part count their disks over the open part only (issue #14: a false depletion
// ring around the obstacle, exactly where the seed expects compression).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>
#include <string>

#include "render/snapshot.hpp"
#include "scenes/src/engines/engine_runner.hpp"
#include "scenes/src/engines/engine_table.hpp"
#include "scenes/src/run/scene_catalog.hpp"
#include "scenes/src/scene/scene.hpp"

namespace grainflow::scenes {
namespace {

TEST(EdFields, BinsAnObstacleCoversInPartAreNotDepleted) {
  // A periodic box at rest with a fixed obstacle: in equilibrium the density next to it
  // is no lower than far away, so a bin it covers in part must not read lower than the
  // rest by its covered share.
  const Scene sc = parse_scene(R"([run]
engine = "ed"
until = 400.0
[system]
box = [60.0, 60.0]
area_fraction = 0.5
kT = 0.02
[boundary.obstacle]
D = 13.0
x = 30.0
y = 30.0
kind = "slip"
[sample]
exposure = 400.0
bins = [20, 20]
)");
  auto runner = find_engine("ed")->make_runner(sc);
  runner->advance_to(0.0);
  render::Snapshot s;
  runner->snapshot("uniform", s);
  while (runner->time() < 400.0) runner->advance_to(400.0);
  runner->snapshot("uniform", s);
  const render::NamedField* density = s.field("density");
  ASSERT_NE(density, nullptr);
  const auto& f = density->field;
  // Bins whose centre lies within 0.4 bin widths outside the obstacle's edge (a third or more
  // of them covered), and
  // bins well away from it.
  double near = 0, far = 0;
  int n_near = 0, n_far = 0;
  for (int iy = 0; iy < f.grid.ny; ++iy)
    for (int ix = 0; ix < f.grid.nx; ++ix) {
      const std::size_t b = f.grid.index(ix, iy);
      if (!f.mask[b]) continue;
      const double r = (f.grid.centre(ix, iy) - Vec2(30, 30)).norm();
      if (r > 6.5 && r < 6.5 + 0.4 * f.grid.dx()) near += f.values[b], ++n_near;
      if (r > 15.0) far += f.values[b], ++n_far;
    }
  ASSERT_GT(n_near, 4);
  ASSERT_GT(n_far, 100);
  near /= n_near;
  far /= n_far;
  // Counted over the whole bin they read ≈ 20 % low, over the area outside the obstacle
  // still 10 % low (centres cannot come within σ/2 of it); over the area open to centres
  // they read a little high: hard disks pile up in a contact layer (g(σ) ≈ 3 at η = 0.5),
  // which is the physics, not the binning.
  EXPECT_GT(near / far, 0.97) << "near " << near << " (" << n_near << " bins), far " << far;
  EXPECT_LT(near / far, 1.3) << "near " << near << " (" << n_near << " bins), far " << far;
  std::printf("  cut bins / far bins: %.3f (%d cut bins)\n", near / far, n_near);
}

TEST(EdFields, EquilibriumGasAroundAnObstacleReadsUniformInEveryBin) {
  // A dilute (η = 0.05, g(σ) ≈ 1.08: no contact layer to speak of), hot (kT = 1: disks
  // cross a bin in a few time units) periodic gas at rest around a fixed obstacle, averaged
  // over 200 exposures. In equilibrium the number density is the same everywhere outside
  // the solid: every bin must read the mean within its noise, the bins the obstacle cuts
  // included. Their noise is larger by 1/√(open fraction) (fewer disks are counted there);
  // the noise itself is measured from the bins the obstacle does not touch. Divided by the
  // whole bin area a bin half covered reads half: ≈ 10 standard deviations low.
  const Scene sc = parse_scene(R"([run]
engine = "ed"
until = 2000.0
[system]
box = [90.0, 90.0]
area_fraction = 0.05
kT = 1.0
[boundary.obstacle]
D = 24.0
x = 45.0
y = 45.0
kind = "slip"
[sample]
exposure = 10.0
bins = [15, 15]
)");
  auto runner = find_engine("ed")->make_runner(sc);
  render::Snapshot s;
  std::vector<double> sum;
  int frames = 0;
  for (double t = 10.0; t <= 2000.0 + 1e-9; t += 10.0) {
    while (runner->time() < t) runner->advance_to(t);
    runner->snapshot("uniform", s);
    const render::NamedField* density = s.field("density");
    ASSERT_NE(density, nullptr);
    ASSERT_TRUE(s.exposure.has_value());
    ASSERT_NEAR(s.exposure->t_end, t, 1e-9);  // a new exposure each time
    sum.resize(density->field.values.size(), 0.0);
    for (std::size_t b = 0; b < sum.size(); ++b)
      if (density->field.mask[b]) sum[b] += density->field.values[b];
    ++frames;
  }
  ASSERT_EQ(frames, 200);
  const auto& f = s.field("density")->field;
  const render::NamedField* open = s.field("open_fraction");
  ASSERT_NE(open, nullptr);
  double mean = 0, var = 0;
  int n_full = 0, n_cut = 0;
  for (std::size_t b = 0; b < sum.size(); ++b)
    if (open->field.values[b] == 1.0) mean += sum[b] / frames, ++n_full;
  mean /= n_full;
  for (std::size_t b = 0; b < sum.size(); ++b)
    if (open->field.values[b] == 1.0) var += std::pow(sum[b] / frames / mean - 1.0, 2);
  const double sd = std::sqrt(var / (n_full - 1));  // relative noise of a whole bin
  ASSERT_GT(n_full, 150);
  EXPECT_LT(sd, 0.05);  // else the test could not see a bin a third covered
  EXPECT_NEAR(mean, 0.05 / (std::numbers::pi / 4), 0.05 * mean);  // n = η / (π σ²/4), less the obstacle's disks
  double worst = 0;
  for (std::size_t b = 0; b < sum.size(); ++b) {
    if (!f.mask[b]) continue;
    const double a = open->field.values[b];
    if (a < 1.0) ++n_cut;
    const double z = (sum[b] / frames / mean - 1.0) / (sd / std::sqrt(a));
    worst = std::max(worst, std::abs(z));
    EXPECT_LT(std::abs(z), 4.5) << "bin " << b << " (open " << a << ") reads " << sum[b] / frames << ", mean " << mean;
  }
  EXPECT_GE(n_cut, 12);
  std::printf("  %d full bins: noise %.3f; %d cut bins; largest |z| %.2f\n", n_full, sd, n_cut, worst);
}

TEST(EdFields, FrameZeroSaysWhenFieldsComeAndTheBarsNameTheirQuantities) {
  // Before the first exposure is over there are no fields: the panels say when they come
  // (not "no density field" three times). Then the bars name the mean speed <|v|>
  // (thermal motion included; the streamline panels draw |<v>| of the mean velocity,
  // which the snapshot carries apart) and the units: σ⁻², σ/τ, 1/τ.
  const Scene sc = parse_scene(R"([run]
engine = "ed"
until = 4.0
[system]
box = [20.0, 20.0]
area_fraction = 0.3
kT = 0.02
[sample]
exposure = 2.5
bins = [4, 4]
)");
  auto runner = find_engine("ed")->make_runner(sc);
  render::Snapshot s;
  runner->snapshot("uniform", s);
  EXPECT_TRUE(s.fields.empty());
  EXPECT_EQ(s.fields_pending, "fields from t = 2.5 τ (first exposure)");
  while (runner->time() < 2.5) runner->advance_to(2.5);
  runner->snapshot("uniform", s);
  EXPECT_TRUE(s.fields_pending.empty()) << s.fields_pending;
  ASSERT_NE(s.field("density"), nullptr);
  EXPECT_EQ(s.field("density")->label, "n [σ⁻²]");
  ASSERT_NE(s.field("speed"), nullptr);
  EXPECT_EQ(s.field("speed")->label, "<|v|> [σ/τ]");  // ED units: σ = m = 1, time in τ
  ASSERT_NE(s.field("vorticity"), nullptr);
  EXPECT_EQ(s.field("vorticity")->label, "ω [1/τ]");
  EXPECT_EQ(s.time_unit, "τ");  // the caption's t = … τ; with σ, the flow-speed bar's |<v>| [σ/τ]
  ASSERT_NE(s.field("temperature"), nullptr);
  EXPECT_EQ(s.field("temperature")->label, "kT");
  ASSERT_TRUE(s.velocity.has_value());
  // <|v|> ≥ |<v>| in every bin (the mean of lengths is at least the length of the mean,
  // equal masses), and by far on the whole: the gas is at rest, its disks are not.
  double mean_speed = 0, speed_of_mean = 0;
  for (std::size_t b = 0; b < s.velocity->values.size(); ++b) {
    EXPECT_GE(s.field("speed")->field.values[b], s.velocity->values[b].norm()) << b;
    mean_speed += s.field("speed")->field.values[b];
    speed_of_mean += s.velocity->values[b].norm();
  }
  EXPECT_GT(mean_speed, 2 * speed_of_mean);
}

TEST(EdFields, BinsAlongAHardWallAreNotDepleted) {
  // Hard walls across y (not periodic): centres keep σ/2 off them, so the bins of the rows
  // along them have 12 % less room than the others and, divided by the whole bin, read
  // 12 % low (7 of the 8 sub-sample rows of a wall bin are open: 0.875). Divided by their
  // open part they read higher than the middle, by the contact layer at a wall (≈ 1.1 at
  // η = 0.5, as at the obstacle); counted over the whole bin they would read ≈ 0.97.
  const Scene sc = parse_scene(R"([run]
engine = "ed"
until = 300.0
[system]
box = [40.0, 41.0]
area_fraction = 0.5
kT = 0.02
[boundary]
periodic = [true, false]
[sample]
exposure = 300.0
bins = [10, 10]
)");
  auto runner = find_engine("ed")->make_runner(sc);
  render::Snapshot s;
  while (runner->time() < 300.0) runner->advance_to(300.0);
  runner->snapshot("uniform", s);
  const render::NamedField* density = s.field("density");
  ASSERT_NE(density, nullptr);
  const auto& f = density->field;
  double wall = 0, middle = 0;
  for (int ix = 0; ix < f.grid.nx; ++ix) {
    wall += f.values[f.grid.index(ix, 0)] + f.values[f.grid.index(ix, f.grid.ny - 1)];
    for (int iy = 3; iy < f.grid.ny - 3; ++iy) middle += f.values[f.grid.index(ix, iy)];
  }
  wall /= 2 * f.grid.nx;
  middle /= (f.grid.ny - 6) * f.grid.nx;
  EXPECT_GT(wall / middle, 1.0) << "wall rows " << wall << ", middle " << middle;
  EXPECT_LT(wall / middle, 1.2) << "wall rows " << wall << ", middle " << middle;
  std::printf("  wall rows / middle rows: %.3f\n", wall / middle);
}

}  // namespace
}  // namespace grainflow::scenes
