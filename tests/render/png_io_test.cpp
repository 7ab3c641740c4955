#include "render/output/png_io.hpp"

#include <gtest/gtest.h>
#include <png.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "output_test_support.hpp"

namespace grainflow::render {
namespace {

namespace fs = std::filesystem;
using test::fresh_dir;
using test::random_image;

// Writes a PNG of any colour type / bit depth with raw libpng, as other programs would.
// `rows` holds packed samples as the PNG stores them (16-bit big-endian).
void write_raw_png(const fs::path& path, int w, int h, int color_type, int bit_depth,
                   const std::vector<std::vector<png_byte>>& rows, const std::vector<png_color>& palette = {},
                   const std::vector<png_byte>& trns = {}, bool interlaced = false) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, f);
  png_set_IHDR(png, info, w, h, bit_depth, color_type, interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  if (!palette.empty()) png_set_PLTE(png, info, palette.data(), int(palette.size()));
  if (!trns.empty()) png_set_tRNS(png, info, trns.data(), int(trns.size()), nullptr);
  png_write_info(png, info);
  std::vector<png_bytep> ptrs;
  for (const auto& r : rows) ptrs.push_back(const_cast<png_bytep>(r.data()));
  png_write_image(png, ptrs.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
}

void expect_identical(const Image& a, const Image& b) {
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  ASSERT_EQ(a.rgba.size(), b.rgba.size());
  std::size_t diffs = 0;
  for (std::size_t i = 0; i < a.rgba.size(); ++i) diffs += a.rgba[i] != b.rgba[i];
  EXPECT_EQ(diffs, 0u);
}

TEST(PngIo, RoundTripIsExactForOddAndEvenSizes) {
  const fs::path dir = fresh_dir();
  const int sizes[][2] = {{1, 1}, {2, 2}, {17, 5}, {33, 31}, {64, 3}};
  std::uint64_t seed = 1;
  for (const auto& s : sizes)
    for (const PngOptions opt : {PngOptions{}, PngOptions{6, true}, PngOptions{0, false}, PngOptions{9, true}}) {
      SCOPED_TRACE(std::to_string(s[0]) + "x" + std::to_string(s[1]) + " level " +
                   std::to_string(opt.compression_level));
      const Image im = random_image(s[0], s[1], seed++);
      const fs::path p = dir / "rt.png";
      write_png(p, im, opt);
      expect_identical(read_png(p), im);
    }
  int n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
  EXPECT_EQ(n, 1) << "no temporary files left behind";
}

// PNG colour type: IHDR's byte 9 (file offset 8 signature + 8 chunk header + 9).
int stored_color_type(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  char header[26] = {0};
  in.read(header, sizeof(header));
  return static_cast<unsigned char>(header[25]);
}

TEST(PngIo, OpaqueImagesAreStoredAsRgbAndReadBackOpaque) {
  const fs::path dir = fresh_dir();
  Image im = random_image(31, 9, 4);
  for (std::size_t i = 3; i < im.rgba.size(); i += 4) im.rgba[i] = 255;
  write_png(dir / "opaque.png", im);
  EXPECT_EQ(stored_color_type(dir / "opaque.png"), PNG_COLOR_TYPE_RGB);
  expect_identical(read_png(dir / "opaque.png"), im);
  im.pixel(30, 8)[3] = 254;  // a single translucent pixel keeps the alpha channel
  write_png(dir / "alpha.png", im);
  EXPECT_EQ(stored_color_type(dir / "alpha.png"), PNG_COLOR_TYPE_RGB_ALPHA);
  expect_identical(read_png(dir / "alpha.png"), im);
}

TEST(PngIo, FiltersAndLevelChangeTheFileNotThePixels) {
  const fs::path dir = fresh_dir();
  const Image im = test::smooth_pattern(200, 100, 0.0);
  write_png(dir / "fast.png", im, {1, false});
  write_png(dir / "small.png", im, {9, true});
  EXPECT_LT(fs::file_size(dir / "small.png"), fs::file_size(dir / "fast.png"))
      << "level 9 with filters must compress a smooth image better than level 1 without";
  expect_identical(read_png(dir / "fast.png"), read_png(dir / "small.png"));
}

TEST(PngIo, ReadsGray8AsOpaqueRgb) {
  const fs::path p = fresh_dir() / "g8.png";
  write_raw_png(p, 3, 2, PNG_COLOR_TYPE_GRAY, 8, {{0, 128, 255}, {1, 2, 3}});
  const Image im = read_png(p);
  ASSERT_EQ(im.width, 3);
  ASSERT_EQ(im.height, 2);
  const std::uint8_t* q = im.pixel(1, 0);
  EXPECT_EQ(q[0], 128);
  EXPECT_EQ(q[1], 128);
  EXPECT_EQ(q[2], 128);
  EXPECT_EQ(q[3], 255);
  EXPECT_EQ(im.pixel(2, 1)[0], 3);
  EXPECT_EQ(im.pixel(2, 1)[3], 255);
}

TEST(PngIo, Reads16BitGrayScaledWithoutGamma) {
  const fs::path p = fresh_dir() / "g16.png";
  // big-endian samples: 0, 257*100 (exactly 100), 65535, 32768
  const std::vector<std::uint16_t> v = {0, 25700, 65535, 32768};
  std::vector<png_byte> row;
  for (auto s : v) {
    row.push_back(png_byte(s >> 8));
    row.push_back(png_byte(s & 0xff));
  }
  write_raw_png(p, 4, 1, PNG_COLOR_TYPE_GRAY, 16, {row});
  const Image im = read_png(p);
  EXPECT_EQ(im.pixel(0, 0)[0], 0);
  EXPECT_EQ(im.pixel(1, 0)[0], 100);
  EXPECT_EQ(im.pixel(2, 0)[0], 255);
  EXPECT_EQ(im.pixel(3, 0)[1], 128) << "32768/257 = 127.5: a linear-to-sRGB conversion would give ~188";
  EXPECT_EQ(im.pixel(3, 0)[3], 255);
}

TEST(PngIo, Reads16BitRgbaAndInterlaced) {
  const fs::path p = fresh_dir() / "rgba16.png";
  const int w = 9, h = 7;  // odd sizes exercise every Adam7 pass
  std::vector<std::vector<png_byte>> rows(h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 4; ++c) {
        const std::uint16_t s = std::uint16_t(257 * ((x * 20 + y * 7 + c * 50) % 256));
        rows[y].push_back(png_byte(s >> 8));
        rows[y].push_back(png_byte(s & 0xff));
      }
  write_raw_png(p, w, h, PNG_COLOR_TYPE_RGB_ALPHA, 16, rows, {}, {}, /*interlaced=*/true);
  const Image im = read_png(p);
  ASSERT_EQ(im.width, w);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 4; ++c) ASSERT_EQ(im.pixel(x, y)[c], (x * 20 + y * 7 + c * 50) % 256) << x << "," << y;
}

TEST(PngIo, ReadsPaletteWithTransparencyAnd1BitGray) {
  const fs::path dir = fresh_dir();
  write_raw_png(dir / "pal.png", 2, 1, PNG_COLOR_TYPE_PALETTE, 8, {{0, 1}}, {{10, 20, 30}, {200, 100, 50}}, {0});
  const Image pal = read_png(dir / "pal.png");
  EXPECT_EQ(pal.pixel(0, 0)[0], 10);
  EXPECT_EQ(pal.pixel(0, 0)[3], 0) << "tRNS entry 0 makes palette index 0 transparent";
  EXPECT_EQ(pal.pixel(1, 0)[1], 100);
  EXPECT_EQ(pal.pixel(1, 0)[3], 255);

  write_raw_png(dir / "g1.png", 8, 1, PNG_COLOR_TYPE_GRAY, 1, {{0b10100000}});
  const Image g1 = read_png(dir / "g1.png");
  EXPECT_EQ(g1.pixel(0, 0)[0], 255);
  EXPECT_EQ(g1.pixel(1, 0)[0], 0);
  EXPECT_EQ(g1.pixel(2, 0)[2], 255);
  EXPECT_EQ(g1.pixel(7, 0)[0], 0);
}

TEST(PngIo, ReadsRgb8WithoutAlpha) {
  const fs::path p = fresh_dir() / "rgb.png";
  write_raw_png(p, 2, 1, PNG_COLOR_TYPE_RGB, 8, {{1, 2, 3, 250, 251, 252}});
  const Image im = read_png(p);
  EXPECT_EQ(im.pixel(1, 0)[0], 250);
  EXPECT_EQ(im.pixel(1, 0)[2], 252);
  EXPECT_EQ(im.pixel(1, 0)[3], 255);
}

std::string error_of(const fs::path& p) {
  try {
    read_png(p);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(PngIo, MissingFileIsAnErrorNamingIt) {
  const fs::path p = fresh_dir() / "absent.png";
  const std::string msg = error_of(p);
  EXPECT_NE(msg.find(p.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("No such file"), std::string::npos) << msg;
}

TEST(PngIo, NonPngIsAnError) {
  const fs::path dir = fresh_dir();
  { std::ofstream(dir / "text.png") << "this is not an image\n"; }
  { std::ofstream(dir / "empty.png"); }
  EXPECT_NE(error_of(dir / "text.png").find("not a PNG"), std::string::npos);
  EXPECT_NE(error_of(dir / "empty.png").find("not a PNG"), std::string::npos);
}

TEST(PngIo, TruncatedAndCorruptedFilesAreErrors) {
  const fs::path dir = fresh_dir();
  write_png(dir / "good.png", random_image(40, 30, 7));
  std::string bytes;
  {
    std::ifstream in(dir / "good.png", std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  { std::ofstream(dir / "trunc.png", std::ios::binary) << bytes.substr(0, bytes.size() / 2); }
  std::string flipped = bytes;
  const std::size_t idat = flipped.find("IDAT");
  ASSERT_NE(idat, std::string::npos);
  flipped[idat + 100] = char(flipped[idat + 100] ^ 0x5a);  // damage compressed data: CRC mismatch
  { std::ofstream(dir / "flip.png", std::ios::binary) << flipped; }

  const std::string t = error_of(dir / "trunc.png");
  const std::string c = error_of(dir / "flip.png");
  EXPECT_NE(t.find("corrupt PNG"), std::string::npos) << t;
  EXPECT_NE(t.find("trunc.png"), std::string::npos) << t;
  EXPECT_NE(c.find("corrupt PNG"), std::string::npos) << c;
}

TEST(PngIo, WriteErrorsNameThePath) {
  const fs::path dir = fresh_dir();
  EXPECT_THROW(write_png(dir / "missing" / "a.png", random_image(2, 2, 1)), Error);
  EXPECT_THROW(write_png(dir / "empty.png", Image{}), Error);
  EXPECT_THROW(write_png(dir / "lvl.png", random_image(2, 2, 1), {10, false}), Error);
  EXPECT_TRUE(fs::is_empty(dir)) << "failed writes leave nothing behind";
}

}  // namespace
}  // namespace grainflow::render
