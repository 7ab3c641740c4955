#include "render/image/compare.hpp"

#include <gtest/gtest.h>

#include "engine/core/error.hpp"
#include "output_test_support.hpp"

namespace grainflow::render {
namespace {

TEST(CompareImages, IdenticalImagesPassWithZeroMetrics) {
  const Image a = test::random_image(37, 23, 5);
  const CompareResult r = compare_images(a, a);
  EXPECT_TRUE(r.passed);
  EXPECT_EQ(r.max_channel_diff, 0);
  EXPECT_EQ(r.mean_abs_diff, 0.0);
  EXPECT_EQ(r.pixels_over, 0);
  EXPECT_EQ(r.pixel_count, 37 * 23);
  EXPECT_EQ(r.fraction_over, 0.0);
}

// The test that proves the comparator fails on a changed image.
TEST(CompareImages, OneChangedPixelFailsWithFractionOneOverN) {
  const Image a = test::random_image(10, 10, 9);
  Image b = a;
  b.pixel(4, 7)[1] = static_cast<std::uint8_t>(a.pixel(4, 7)[1] < 128 ? a.pixel(4, 7)[1] + 5 : a.pixel(4, 7)[1] - 5);
  const CompareResult r = compare_images(a, b);
  EXPECT_FALSE(r.passed);
  EXPECT_EQ(r.max_channel_diff, 5);
  EXPECT_EQ(r.pixels_over, 1);
  EXPECT_DOUBLE_EQ(r.fraction_over, 1.0 / 100.0);
  EXPECT_DOUBLE_EQ(r.mean_abs_diff, 5.0 / 400.0) << "mean over all pixels and all four channels";
}

TEST(CompareImages, ToleranceSemantics) {
  const Image a = test::random_image(10, 10, 11);
  Image b = a;
  b.pixel(0, 0)[0] = static_cast<std::uint8_t>(a.pixel(0, 0)[0] ^ 0x04);  // |d| = 4
  b.pixel(9, 9)[2] = static_cast<std::uint8_t>(a.pixel(9, 9)[2] ^ 0x20);  // |d| = 32
  // Per-pixel tolerance: "over" means strictly greater than max_channel.
  EXPECT_EQ(compare_images(a, b, {3, 0.0}).pixels_over, 2);
  EXPECT_EQ(compare_images(a, b, {4, 0.0}).pixels_over, 1);
  EXPECT_EQ(compare_images(a, b, {31, 0.0}).pixels_over, 1);
  EXPECT_TRUE(compare_images(a, b, {32, 0.0}).passed);
  // Allowed fraction: passes when fraction_over <= max_fraction.
  EXPECT_TRUE(compare_images(a, b, {4, 0.01}).passed);
  EXPECT_FALSE(compare_images(a, b, {4, 0.0099}).passed);
  EXPECT_TRUE(compare_images(a, b, {0, 0.02}).passed);
  EXPECT_FALSE(compare_images(a, b, {0, 0.015}).passed);
  // Metrics do not depend on the tolerances.
  EXPECT_EQ(compare_images(a, b, {0, 0.0}).max_channel_diff, 32);
  EXPECT_DOUBLE_EQ(compare_images(a, b, {100, 1.0}).mean_abs_diff, 36.0 / 400.0);
}

TEST(CompareImages, AlphaCounts) {
  Image a(3, 3), b(3, 3);
  b.pixel(1, 1)[3] = 1;
  const CompareResult r = compare_images(a, b);
  EXPECT_FALSE(r.passed);
  EXPECT_EQ(r.max_channel_diff, 1);
}

TEST(CompareImages, SizeMismatchAndBadOptionsAreErrors) {
  const Image a(8, 6), b(6, 8);
  try {
    compare_images(a, b);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("8x6 vs 6x8"), std::string::npos) << e.what();
  }
  EXPECT_THROW(compare_images(a, a, {256, 0.0}), Error);
  EXPECT_THROW(compare_images(a, a, {0, 1.5}), Error);
  EXPECT_THROW(compare_images(a, a, {-1, 0.0}), Error);
  EXPECT_THROW(compare_images(Image{}, Image{}), Error);
  EXPECT_THROW(diff_heatmap(a, b), Error);
}

int brightness(const std::uint8_t* p) { return p[0] + p[1] + p[2]; }

TEST(DiffHeatmap, BlackWhereEqualVisibleForOneLevelAndBrighterForLarger) {
  Image a(5, 1), b(5, 1);
  const int deltas[5] = {0, 1, 10, 100, 255};
  for (int x = 0; x < 5; ++x) b.pixel(x, 0)[x % 3] = static_cast<std::uint8_t>(deltas[x]);
  const Image h = diff_heatmap(a, b);
  ASSERT_EQ(h.width, 5);
  EXPECT_EQ(brightness(h.pixel(0, 0)), 0);
  EXPECT_GT(brightness(h.pixel(1, 0)), 120) << "a one-level change must be plainly visible";
  for (int x = 1; x < 5; ++x) EXPECT_GT(brightness(h.pixel(x, 0)), brightness(h.pixel(x - 1, 0)));
  EXPECT_EQ(h.pixel(4, 0)[0], 0xfc);  // top of inferno: pale yellow
  EXPECT_EQ(h.pixel(4, 0)[1], 0xff);
  EXPECT_EQ(h.pixel(4, 0)[2], 0xa4);
  for (int x = 0; x < 5; ++x) EXPECT_EQ(h.pixel(x, 0)[3], 255);
}

}  // namespace
}  // namespace grainflow::render
