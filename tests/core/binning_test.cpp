// Binned fields (seed 003 §4.1, Eq. 4.9): hand-computed bins, exposure averages, and the
// granular temperature recovered from synthetic Maxwellian velocities.
#include "engine/core/binning.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <span>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/core/rng.hpp"

using namespace grainflow;
using namespace grainflow::core;

namespace {

BinningOptions grid2x2() {
  BinningOptions o;
  o.grid.nx = 2;
  o.grid.ny = 2;
  o.grid.lo = Vec2(0, 0);
  o.grid.hi = Vec2(2, 2);  // unit bins
  return o;
}

ParticleFrame frame2d(std::vector<Vec3> pos, std::vector<Vec3> vel, std::vector<double> radius) {
  ParticleFrame f;
  f.dim = 2;
  const std::size_t n = pos.size();
  f.position = std::move(pos);
  f.velocity = std::move(vel);
  f.radius = std::move(radius);
  for (std::size_t i = 0; i < n; ++i) f.id.push_back(static_cast<std::int64_t>(i) + 1), f.type.push_back(1);
  return f;
}

}  // namespace

TEST(Binning, HandComputed2D) {
  // bin (0,0): v = (1,0), (3,2); bin (1,0): v = (0,−1); bins (0,1), (1,1) empty; one outside.
  const auto f = frame2d({{0.5, 0.5, 0}, {0.2, 0.7, 0}, {1.5, 0.25, 0}, {5.0, 0.5, 0}},
                         {{1, 0, 0}, {3, 2, 0}, {0, -1, 0}, {9, 9, 0}}, {0.1, 0.2, 0.3, 0.4});
  const auto b = bin_frame(f, grid2x2());
  EXPECT_DOUBLE_EQ(b.density.at(0, 0), 2.0);
  EXPECT_DOUBLE_EQ(b.density.at(1, 0), 1.0);
  EXPECT_DOUBLE_EQ(b.density.at(0, 1), 0.0);  // a measured zero, not missing data
  EXPECT_TRUE(b.density.valid(0, 1));
  ASSERT_TRUE(b.fraction);
  EXPECT_NEAR(b.fraction->at(0, 0), std::numbers::pi * (0.01 + 0.04), 1e-15);
  EXPECT_NEAR(b.fraction->at(1, 0), std::numbers::pi * 0.09, 1e-15);
  ASSERT_TRUE(b.mean_velocity && b.temperature && b.mean_speed);
  EXPECT_EQ(b.mean_velocity->at(0, 0), Vec2(2, 1));
  EXPECT_EQ(b.mean_velocity->at(1, 0), Vec2(0, -1));
  // kT = (m/i)<|C|²> = (1/2)·((1 + 1) + (1 + 1))/2 = 1
  EXPECT_NEAR(b.temperature->at(0, 0), 1.0, 1e-14);
  EXPECT_FALSE(b.temperature->valid(1, 0));  // one sample: no fluctuation to measure
  EXPECT_TRUE(std::isnan(b.temperature->at(1, 0)));
  EXPECT_NEAR(b.mean_speed->at(0, 0), (1.0 + std::sqrt(13.0)) / 2.0, 1e-14);
  EXPECT_DOUBLE_EQ(b.mean_speed->at(1, 0), 1.0);
  for (int ix = 0; ix < 2; ++ix) {
    EXPECT_FALSE(b.mean_velocity->valid(ix, 1));
    EXPECT_TRUE(std::isnan(b.mean_velocity->at(ix, 1).x()));
    EXPECT_FALSE(b.mean_speed->valid(ix, 1));
    EXPECT_FALSE(b.temperature->valid(ix, 1));
  }
  BinAccumulator acc(grid2x2());
  acc.add(f);
  EXPECT_EQ(acc.outside(), 1u);
  EXPECT_EQ(acc.counts()[0], 2u);
}

TEST(Binning, MassWeightedMeanAndTemperature) {
  // m = 1, 3 with v = (1,0), (3,2): u = (2.5, 1.5); Σm|v−u|² = 4.5 + 1.5 = 6; kT = 6/(2·2).
  BinAccumulator acc(grid2x2());
  const std::vector<Vec2> p{{0.5, 0.5}, {0.6, 0.6}}, v{{1, 0}, {3, 2}};
  const std::vector<double> m{1, 3};
  acc.add(p, v, {}, m);
  EXPECT_NEAR(acc.mean_velocity().at(0, 0).x(), 2.5, 1e-15);
  EXPECT_NEAR(acc.mean_velocity().at(0, 0).y(), 1.5, 1e-15);
  EXPECT_NEAR(acc.temperature().at(0, 0), 1.5, 1e-14);
  EXPECT_THROW(acc.fraction(), Error);  // no radii given
}

TEST(Binning, ExposureAverageOverFrames) {
  // Same bin, v = (+1, 0) in frame 1 and (−1, 0) in frame 2: the exposure mean is 0 and
  // both samples are fluctuations, kT = (1 + 1)/2/2 = 0.5; density = 2 samples / 2 frames.
  BinAccumulator acc(grid2x2());
  acc.add(frame2d({{0.5, 0.5, 0}}, {{1, 0, 0}}, {0.5}));
  acc.add(frame2d({{0.4, 0.5, 0}}, {{-1, 0, 0}}, {0.5}));
  EXPECT_EQ(acc.frames(), 2);
  EXPECT_DOUBLE_EQ(acc.density().at(0, 0), 1.0);
  EXPECT_NEAR(acc.fraction().at(0, 0), std::numbers::pi * 0.25, 1e-15);
  EXPECT_NEAR(acc.mean_velocity().at(0, 0).norm(), 0.0, 1e-15);
  EXPECT_NEAR(acc.temperature().at(0, 0), 0.5, 1e-15);
  acc.reset();
  EXPECT_EQ(acc.frames(), 0);
  EXPECT_EQ(acc.density().at(0, 0), 0.0);
}

TEST(Binning, MaxwellianTemperature2D) {
  // Velocities U + sqrt(kT/m)·N(0,1) per component; 4×4 bins of 12 500 particles: the
  // relative sd of kT per bin is 1/sqrt(N) ≈ 0.9 %, so 4 % is > 4 sd.
  const double kT = 0.02, m = 1.0;
  const Vec2 U(0.1, -0.05);
  Rng rng(2003);
  const int n = 200000;
  std::vector<Vec2> p(n), v(n);
  for (int i = 0; i < n; ++i) {
    p[i] = Vec2(rng.uniform(0, 10), rng.uniform(0, 10));
    v[i] = U + std::sqrt(kT / m) * Vec2(rng.normal(), rng.normal());
  }
  BinningOptions o;
  o.grid.nx = o.grid.ny = 4;
  o.grid.hi = Vec2(10, 10);
  BinAccumulator acc(o);
  acc.add(p, v);
  const auto T = acc.temperature();
  const auto u = acc.mean_velocity();
  const auto rho = acc.density();
  double mean_T = 0;
  for (int iy = 0; iy < 4; ++iy)
    for (int ix = 0; ix < 4; ++ix) {
      EXPECT_NEAR(T.at(ix, iy), kT, 0.04 * kT) << ix << "," << iy;
      EXPECT_NEAR((u.at(ix, iy) - U).norm(), 0.0, 5 * std::sqrt(2 * kT / 12500.0));
      EXPECT_NEAR(rho.at(ix, iy), n / 100.0, 5 * std::sqrt(12500.0) / 6.25);
      mean_T += T.at(ix, iy) / 16;
    }
  EXPECT_NEAR(mean_T, kT, 0.01 * kT);
}

TEST(Binning, MaxwellianTemperature3DSlabAndMass) {
  // 3D, m = 2 from the "mass" column, binned in the xz plane over a slab 2 < y < 6:
  // i = 3 degrees of freedom.
  const double kT = 0.5, m = 2.0;
  Rng rng(7);
  ParticleFrame f;
  f.dim = 3;
  f.has_box = true;
  f.box_lo = Vec3(0, 0, 0);
  f.box_hi = Vec3(4, 8, 4);
  std::vector<double> mass;
  const int n = 120000;
  for (int i = 0; i < n; ++i) {
    f.id.push_back(i + 1);
    f.type.push_back(1);
    f.position.emplace_back(rng.uniform(0, 4), rng.uniform(0, 8), rng.uniform(0, 4));
    f.velocity.emplace_back(Vec3(1, 2, 3) + std::sqrt(kT / m) * Vec3(rng.normal(), rng.normal(), rng.normal()));
    f.radius.push_back(0.1);
    mass.push_back(m);
  }
  f.extra.emplace_back("mass", mass);
  BinningOptions o;
  o.plane = BinPlane::xz;
  o.grid.nx = o.grid.ny = 2;
  o.grid.hi = Vec2(4, 4);
  o.slab_lo = 2.0;
  o.slab_hi = 6.0;
  const auto b = bin_frame(f, o);
  for (int k = 0; k < 4; ++k) {
    // ~15 000 samples per bin: relative sd of kT ≈ sqrt(2/(3N)) ≈ 0.7 %.
    EXPECT_NEAR(b.temperature->values[k], kT, 0.04 * kT);
    EXPECT_NEAR(b.mean_velocity->values[k].x(), 1.0, 0.02);  // in-plane components: x and z
    EXPECT_NEAR(b.mean_velocity->values[k].y(), 3.0, 0.02);
    // projected density: half the particles (the slab) over 16 area units
    EXPECT_NEAR(b.density.values[k], n / 2.0 / 16.0, 0.05 * n / 32.0);
    // solid fraction = N_bin (4/3)π r³ / (bin area 4 × slab 4)
    EXPECT_NEAR(b.fraction->values[k], b.density.values[k] * 4 * (4.0 / 3.0) * std::numbers::pi * 1e-3 / 16.0, 1e-12);
  }
}

TEST(Binning, SolidFractionFromBoxThickness) {
  // One sphere r = 0.5 in a unit bin; slab = box z extent 2 → fraction = (π/6)/2.
  ParticleFrame f;
  f.dim = 3;
  f.has_box = true;
  f.box_lo = Vec3(0, 0, 0);
  f.box_hi = Vec3(1, 1, 2);
  f.position = {Vec3(0.5, 0.5, 1.0)};
  f.radius = {0.5};
  f.id = {1};
  f.type = {1};
  BinningOptions o;
  o.grid.nx = o.grid.ny = 1;
  const auto b = bin_frame(f, o);
  ASSERT_TRUE(b.fraction);
  EXPECT_NEAR(b.fraction->at(0, 0), std::numbers::pi / 6.0 / 2.0, 1e-15);
  EXPECT_FALSE(b.mean_velocity);
  f.has_box = false;
  BinAccumulator acc(o);
  acc.add(f);
  EXPECT_THROW(acc.fraction(), Error);
  EXPECT_THROW(acc.mean_velocity(), Error);
}

TEST(Binning, RejectsInconsistentUse) {
  BinningOptions o = grid2x2();
  o.plane = BinPlane::yz;
  BinAccumulator acc(o);
  EXPECT_THROW(acc.add(frame2d({{0.5, 0.5, 0}}, {}, {0.5})), Error);
  BinAccumulator acc2(grid2x2());
  acc2.add(frame2d({{0.5, 0.5, 0}}, {}, {0.5}));
  const std::vector<Vec3> p3{Vec3(0.5, 0.5, 0.5)};
  EXPECT_THROW(acc2.add(std::span<const Vec3>(p3), std::span<const Vec3>()), Error);
  BinningOptions bad = grid2x2();
  bad.grid.nx = 0;
  EXPECT_THROW(BinAccumulator{bad}, Error);
  bad = grid2x2();
  bad.slab_lo = 1.0;
  EXPECT_THROW(BinAccumulator{bad}, Error);
}

// The one set-up of 3D field planes (DEM sample.plane/bins/slab, render --plane/--bins/--slab).
TEST(Binning, PlaneBinningSpansThePlaneAxesAndKeepsTheSlab) {
  const Vec3 lo(1, 2, 3), hi(5, 8, 13);
  const BinningOptions xz = plane_binning(bin_plane("xz"), lo, hi, {4, 10}, std::array{3.0, 5.0});
  EXPECT_EQ(xz.plane, BinPlane::xz);
  EXPECT_EQ(xz.grid.nx, 4);
  EXPECT_EQ(xz.grid.ny, 10);
  EXPECT_EQ(xz.grid.lo, Vec2(1, 3));
  EXPECT_EQ(xz.grid.hi, Vec2(5, 13));
  EXPECT_EQ(*xz.slab_lo, 3.0);
  EXPECT_EQ(*xz.slab_hi, 5.0);
  const BinningOptions yz = plane_binning(BinPlane::yz, lo, hi, {6, 10});
  EXPECT_EQ(yz.grid.lo, Vec2(2, 3));
  EXPECT_EQ(yz.grid.hi, Vec2(8, 13));
  EXPECT_FALSE(yz.slab_lo.has_value());
  EXPECT_EQ(plane_normal(BinPlane::xy), 2);
  EXPECT_EQ(plane_normal(BinPlane::xz), 1);
  EXPECT_EQ(plane_normal(BinPlane::yz), 0);
  EXPECT_EQ(plane_axes(BinPlane::yz), (std::array{1, 2}));
  EXPECT_THROW(bin_plane("zx"), Error);
  // Only particles inside the slab are binned.
  BinAccumulator acc(xz);
  const std::vector<Vec3> x = {{2, 4, 4}, {2, 5.5, 4}, {2, 2.5, 4}};
  acc.add(std::span<const Vec3>(x), {}, {}, {}, 0.0);
  EXPECT_EQ(acc.outside(), 2u);
}

// Default 3D bins: never narrower than the width asked for (two diameters), at least one.
TEST(Binning, BinsNoFinerThanTheWidth) {
  EXPECT_EQ(bins_no_finer_than(Vec2(0.04, 0.08), 0.002), (std::array{20, 40}));
  EXPECT_EQ(bins_no_finer_than(Vec2(0.041, 0.0399), 0.002), (std::array{20, 19}));
  EXPECT_EQ(bins_no_finer_than(Vec2(0.001, 0.04), 0.002), (std::array{1, 20}));
  EXPECT_EQ(bins_no_finer_than(Vec2(1e6, 1.0), 1e-3), (std::array{4096, 1000}));
}
