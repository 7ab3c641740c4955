// The fields an ED run draws, as the runner hands them to the renderer: bins an obstacle
// covers in part count their disks over the open part only (issue #14: a false depletion
// ring around the obstacle, exactly where the seed expects compression).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
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
