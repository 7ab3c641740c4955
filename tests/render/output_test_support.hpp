// Test images and scratch directories shared by the output tests (tests/render/*_test.cpp):
// a smooth moving pattern (what H.264 must reproduce closely), random noise (what PNG
// must reproduce exactly), and a fresh directory per test under GRAINFLOW_TEST_OUT.
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "engine/core/rng.hpp"
#include "render/image/image.hpp"

namespace grainflow::render::test {

// The whole file as bytes ("" when it cannot be read).
inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// An empty directory named after the running test.
inline std::filesystem::path fresh_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path dir =
      std::filesystem::path(GRAINFLOW_TEST_OUT) / (std::string(info->test_suite_name()) + "." + info->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// Soft gradients and a blob moving with `phase`: smooth enough that a good H.264 encode
// stays within a few levels of it.
inline Image smooth_pattern(int w, int h, double phase) {
  Image im(w, h);
  const double cx = w * (0.3 + 0.4 * (0.5 + 0.5 * std::sin(phase)));
  const double cy = h * 0.5;
  const double r2 = 0.04 * double(w) * double(w);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double u = double(x) / w, v = double(y) / h;
      const double blob = std::exp(-((x - cx) * (x - cx) + (y - cy) * (y - cy)) / r2);
      std::uint8_t* p = im.pixel(x, y);
      p[0] = static_cast<std::uint8_t>(std::lround(40 + 150 * u + 60 * blob));
      p[1] = static_cast<std::uint8_t>(std::lround(60 + 120 * v + 40 * blob));
      p[2] = static_cast<std::uint8_t>(std::lround(180 - 100 * u * v + 20 * blob));
      p[3] = 255;
    }
  return im;
}

// Every byte random, alpha included: a lossless format must return it bit for bit.
inline Image random_image(int w, int h, std::uint64_t seed) {
  Image im(w, h);
  core::Rng rng(seed);
  for (auto& b : im.rgba) b = static_cast<std::uint8_t>(rng.below(256));
  return im;
}

}  // namespace grainflow::render::test
