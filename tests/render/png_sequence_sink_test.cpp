#include "render/output/png_sequence_sink.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "engine/core/error.hpp"
#include "output_test_support.hpp"

namespace grainflow::render {
namespace {

namespace fs = std::filesystem;

TEST(PngSequenceSink, WritesZeroPaddedFramesIntoCreatedDirectory) {
  const fs::path dir = test::fresh_dir() / "run" / "frames";
  PngSequenceSink sink(dir);
  EXPECT_TRUE(fs::is_directory(dir));
  for (int k = 0; k < 3; ++k) sink.consume(test::random_image(13, 7, 100 + k), k, 0.5 * k);
  sink.consume(test::random_image(13, 7, 999), 1234567, 1.0);
  sink.finish();
  EXPECT_EQ(sink.frames_written(), 4);
  EXPECT_EQ(sink.frame_path(0).filename(), "frame_000000.png");
  for (int k = 0; k < 3; ++k) {
    const Image got = read_png(dir / ("frame_00000" + std::to_string(k) + ".png"));
    EXPECT_EQ(got.rgba, test::random_image(13, 7, 100 + k).rgba);
  }
  EXPECT_TRUE(fs::exists(dir / "frame_1234567.png"));
  int n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
  EXPECT_EQ(n, 4);
}

TEST(PngSequenceSink, DirectoryThatIsAFileAndNegativeIndexAreErrors) {
  const fs::path dir = test::fresh_dir();
  { std::ofstream(dir / "plain") << "x"; }
  EXPECT_THROW(PngSequenceSink(dir / "plain"), Error);
  PngSequenceSink sink(dir / "frames");
  EXPECT_THROW(sink.consume(test::random_image(2, 2, 1), -1, 0.0), Error);
}

}  // namespace
}  // namespace grainflow::render
