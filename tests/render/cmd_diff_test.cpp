// Runs the built `grainflow diff` as a user would and checks its exit status and output.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>

#include "render/output/png_io.hpp"
#include "output_test_support.hpp"

namespace grainflow::render {
namespace {

namespace fs = std::filesystem;

struct CliRun {
  int status = -1;
  std::string out;
};

// Built with append: GCC 12 gives a false -Wrestrict on `"literal" + std::string` (PR 105329).
std::string quoted(const std::string& s) {
  std::string r;
  r.reserve(s.size() + 2);
  r += '\'';
  r += s;
  r += '\'';
  return r;
}

CliRun grainflow(const std::string& args, const fs::path& dir) {
  const fs::path log = dir / "stdout.txt";
  std::string cmd = quoted(GRAINFLOW_EXE);
  cmd += ' ';
  cmd += args;
  cmd += " > ";
  cmd += quoted(log.string());
  cmd += " 2>&1";
  const int raw = std::system(cmd.c_str());
  CliRun r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  std::ifstream in(log);
  r.out.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return r;
}

class DiffCommand : public ::testing::Test {
protected:
  void SetUp() override {
    dir = test::fresh_dir();
    a = dir / "a.png";
    b = dir / "b.png";
    const Image im = test::random_image(20, 10, 3);
    write_png(a, im);
    Image changed = im;
    changed.pixel(3, 3)[0] = static_cast<std::uint8_t>(im.pixel(3, 3)[0] ^ 0x08);  // one pixel, |d| = 8
    write_png(b, changed);
  }
  std::string q(const fs::path& p) const { return quoted(p.string()); }
  fs::path dir, a, b;
};

TEST_F(DiffCommand, IdenticalImagesExitZero) {
  const CliRun r = grainflow("diff " + q(a) + " " + q(a), dir);
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("max channel difference: 0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("within tolerance"), std::string::npos) << r.out;
}

TEST_F(DiffCommand, ChangedPixelExitsOneAndReportsMetrics) {
  const CliRun r = grainflow("diff " + q(a) + " " + q(b), dir);
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_NE(r.out.find("max channel difference: 8"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("mean absolute difference: 0.010000"), std::string::npos) << r.out;  // 8 / 800
  EXPECT_NE(r.out.find("fraction 0.005"), std::string::npos) << r.out;                     // 1 / 200
  EXPECT_NE(r.out.find("DIFFERENT"), std::string::npos) << r.out;
}

TEST_F(DiffCommand, TolerancesMakeItPass) {
  EXPECT_EQ(grainflow("diff " + q(a) + " " + q(b) + " --max-channel 8", dir).status, 0);
  EXPECT_EQ(grainflow("diff " + q(a) + " " + q(b) + " --max-channel 7", dir).status, 1);
  EXPECT_EQ(grainflow("diff " + q(a) + " " + q(b) + " --max-fraction 0.005", dir).status, 0);
  EXPECT_EQ(grainflow("diff " + q(a) + " " + q(b) + " --max-fraction 0.004", dir).status, 1);
}

TEST_F(DiffCommand, WritesHeatMap) {
  const fs::path out = dir / "heat.png";
  EXPECT_EQ(grainflow("diff " + q(a) + " " + q(b) + " --out " + q(out), dir).status, 1);
  const Image h = read_png(out);
  ASSERT_EQ(h.width, 20);
  ASSERT_EQ(h.height, 10);
  EXPECT_EQ(h.pixel(0, 0)[0] + h.pixel(0, 0)[1] + h.pixel(0, 0)[2], 0);
  EXPECT_GT(h.pixel(3, 3)[0] + h.pixel(3, 3)[1] + h.pixel(3, 3)[2], 100);
}

TEST_F(DiffCommand, ErrorsExitTwo) {
  { std::ofstream(dir / "text.png") << "hello"; }
  write_png(dir / "small.png", test::random_image(10, 10, 1));
  const CliRun missing = grainflow("diff " + q(a) + " " + q(dir / "absent.png"), dir);
  EXPECT_EQ(missing.status, 2) << missing.out;
  EXPECT_NE(missing.out.find("absent.png"), std::string::npos) << missing.out;
  EXPECT_EQ(grainflow("diff " + q(a) + " " + q(dir / "text.png"), dir).status, 2);
  const CliRun size = grainflow("diff " + q(a) + " " + q(dir / "small.png"), dir);
  EXPECT_EQ(size.status, 2) << size.out;
  EXPECT_NE(size.out.find("20x10 vs 10x10"), std::string::npos) << size.out;
  // A header claiming 20000 × 20000 pixels is refused from the header alone, without
  // decoding (the file is a valid 20x10 PNG whose IHDR was rewritten).
  {
    std::string bytes;
    {
      std::ifstream in(a, std::ios::binary);
      bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    for (int at : {16, 20}) bytes.replace(std::size_t(at), 4, std::string("\x00\x00\x4e\x20", 4));
    std::ofstream(dir / "huge_a.png", std::ios::binary) << bytes;
    std::ofstream(dir / "huge_b.png", std::ios::binary) << bytes;
  }
  const CliRun huge = grainflow("diff " + q(dir / "huge_a.png") + " " + q(dir / "huge_b.png"), dir);
  EXPECT_EQ(huge.status, 2) << huge.out;
  EXPECT_NE(huge.out.find("20000x20000; allowed: at most 16384"), std::string::npos) << huge.out;
  const CliRun huge_vs_small = grainflow("diff " + q(dir / "huge_a.png") + " " + q(dir / "small.png"), dir);
  EXPECT_NE(huge_vs_small.out.find("20000x20000 vs 10x10"), std::string::npos) << huge_vs_small.out;
  EXPECT_EQ(grainflow("diff " + q(a) + " " + q(b) + " --max-channel 300", dir).status, 2);
  EXPECT_EQ(grainflow("diff " + q(a), dir).status, 2);
}

}  // namespace
}  // namespace grainflow::render
