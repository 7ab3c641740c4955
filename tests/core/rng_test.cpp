#include "engine/core/rng.hpp"

#include <gtest/gtest.h>

#include <cmath>

using grainflow::core::Rng;

TEST(Rng, SameSeedSameStream) {
  Rng a(42), b(42), c(43);
  for (int i = 0; i < 100; ++i) {
    const auto x = a.next_u64();
    EXPECT_EQ(x, b.next_u64());
    EXPECT_NE(x, c.next_u64());
  }
}

TEST(Rng, PinnedFirstValuesAcrossPlatforms) {
  // splitmix64(0) seeding then xoshiro256**: pinned so any change to the generator (which
  // would change every run's numbers) is a deliberate, visible decision.
  Rng r(0);
  const std::uint64_t first = r.next_u64();
  Rng r2(0);
  EXPECT_EQ(first, r2.next_u64());
  EXPECT_EQ(first, 0x99ec5f36cb75f2b4ULL);
}

TEST(Rng, UniformMomentsAndRange) {
  Rng r(7);
  const int n = 200000;
  double s = 0, s2 = 0;
  for (int i = 0; i < n; ++i) {
    const double u = r.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    s += u;
    s2 += u * u;
  }
  EXPECT_NEAR(s / n, 0.5, 0.005);
  EXPECT_NEAR(s2 / n - (s / n) * (s / n), 1.0 / 12.0, 0.002);
}

TEST(Rng, NormalMoments) {
  Rng r(11);
  const int n = 200000;
  double s = 0, s2 = 0, s4 = 0;
  for (int i = 0; i < n; ++i) {
    const double x = r.normal();
    s += x;
    s2 += x * x;
    s4 += x * x * x * x;
  }
  EXPECT_NEAR(s / n, 0.0, 0.01);
  EXPECT_NEAR(s2 / n, 1.0, 0.01);
  EXPECT_NEAR(s4 / n, 3.0, 0.06);
}

TEST(Rng, BelowIsUnbiasedAndInRange) {
  Rng r(3);
  int counts[7] = {};
  for (int i = 0; i < 70000; ++i) {
    const auto k = r.below(7);
    ASSERT_LT(k, 7u);
    ++counts[k];
  }
  for (int c : counts) EXPECT_NEAR(c, 10000, 400);
}

TEST(Rng, StateRoundTripContinuesStream) {
  Rng a(5);
  a.normal();  // leaves a spare normal in the state
  const auto st = a.state();
  const double x = a.normal();
  const double y = a.uniform();
  Rng b(999);
  b.set_state(st);
  EXPECT_EQ(x, b.normal());
  EXPECT_EQ(y, b.uniform());
}
