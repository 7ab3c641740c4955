// Shared by the golden-image tests: a GL context per backend (null when this machine
// cannot make one, so tests skip cleanly), and the golden comparison that writes the
// actual image and a diff heat map to GRAINFLOW_TEST_OUT on failure.
// GRAINFLOW_UPDATE_GOLDEN=1 rewrites the golden instead (commit it with the reason).
#pragma once
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "engine/core/error.hpp"
#include "render/context/gl_context.hpp"
#include "render/image/compare.hpp"
#include "render/output/png_io.hpp"

namespace grainflow::render::golden {

inline std::unique_ptr<GlContext> context_or_null(Backend b) {
  try {
    return create_context(b);
  } catch (const Error&) {
    return nullptr;
  }
}

inline void check_golden(const Image& actual, const std::string& name, const CompareOptions& tolerance) {
  namespace fs = std::filesystem;
  const fs::path golden = fs::path(GRAINFLOW_GOLDEN_DIR) / (name + ".png");
  if (std::getenv("GRAINFLOW_UPDATE_GOLDEN")) {
    write_png(golden, actual, {6, true});
    GTEST_SKIP() << "golden image rewritten: " << golden;
  }
  ASSERT_TRUE(fs::exists(golden)) << "missing golden image " << golden << " (GRAINFLOW_UPDATE_GOLDEN=1 makes it)";
  const Image expected = read_png(golden);
  const auto r = compare_images(actual, expected, tolerance);
  if (!r.passed) {
    fs::create_directories(GRAINFLOW_TEST_OUT);
    write_png(fs::path(GRAINFLOW_TEST_OUT) / (name + ".actual.png"), actual);
    write_png(fs::path(GRAINFLOW_TEST_OUT) / (name + ".diff.png"), diff_heatmap(actual, expected));
  }
  EXPECT_TRUE(r.passed) << name << ": max channel diff " << r.max_channel_diff << ", mean " << r.mean_abs_diff
                        << ", fraction over " << r.fraction_over << " (actual and diff written to "
                        << GRAINFLOW_TEST_OUT << ")";
}

}  // namespace grainflow::render::golden
