#include "render/image/compare.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <vector>
#include <string>

#include "engine/core/error.hpp"

namespace grainflow::render {

namespace {

std::string size_of(const Image& im) { return std::to_string(im.width) + "x" + std::to_string(im.height); }

void check_pair(const Image& a, const Image& b) {
  if (a.empty() || b.empty())
    throw Error("image comparison: empty image (" + size_of(a) + " vs " + size_of(b) + ")");
  if (a.width != b.width || a.height != b.height)
    throw Error("image comparison: sizes differ (" + size_of(a) + " vs " + size_of(b) +
                "); only images of the same size can be compared");
}

int pixel_max_diff(const std::uint8_t* p, const std::uint8_t* q) {
  int m = 0;
  for (int c = 0; c < 4; ++c) m = std::max(m, std::abs(int(p[c]) - int(q[c])));
  return m;
}

// Inferno (Smith & van der Walt, matplotlib; CC0) at t = 0, 0.1, ..., 1.
constexpr std::array<std::array<std::uint8_t, 3>, 11> kInferno = {{{0x00, 0x00, 0x04},
                                                                   {0x16, 0x0b, 0x39},
                                                                   {0x42, 0x0a, 0x68},
                                                                   {0x6a, 0x17, 0x6e},
                                                                   {0x93, 0x26, 0x67},
                                                                   {0xbc, 0x37, 0x54},
                                                                   {0xdd, 0x51, 0x3a},
                                                                   {0xf3, 0x78, 0x19},
                                                                   {0xfc, 0xa5, 0x0a},
                                                                   {0xf6, 0xd7, 0x46},
                                                                   {0xfc, 0xff, 0xa4}}};

std::array<std::uint8_t, 3> inferno(double t) {
  t = std::clamp(t, 0.0, 1.0) * double(kInferno.size() - 1);
  const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(t), kInferno.size() - 2);
  const double f = t - double(i);
  std::array<std::uint8_t, 3> out{};
  for (int c = 0; c < 3; ++c)
    out[c] = static_cast<std::uint8_t>(std::lround((1.0 - f) * kInferno[i][c] + f * kInferno[i + 1][c]));
  return out;
}

}  // namespace

CompareResult compare_images(const Image& a, const Image& b, const CompareOptions& options) {
  check_pair(a, b);
  if (options.max_channel < 0 || options.max_channel > 255)
    throw Error("image comparison: max channel tolerance " + std::to_string(options.max_channel) +
                " is out of range (allowed 0..255)");
  if (!(options.max_fraction >= 0.0 && options.max_fraction <= 1.0))
    throw Error("image comparison: max fraction " + std::to_string(options.max_fraction) +
                " is out of range (allowed 0..1)");

  CompareResult r;
  r.pixel_count = static_cast<std::int64_t>(a.width) * a.height;
  std::uint64_t sum = 0;  // exact: at most 255 * 4 * 2^32 for a 65536^2 image
  std::uint64_t sq_rgb = 0;  // Σ d² over R, G, B: exact below 2^64 up to 65536² pixels
  for (std::int64_t i = 0; i < r.pixel_count; ++i) {
    const std::uint8_t* p = a.rgba.data() + i * 4;
    const std::uint8_t* q = b.rgba.data() + i * 4;
    int m = 0;
    for (int c = 0; c < 4; ++c) {
      const int d = std::abs(int(p[c]) - int(q[c]));
      sum += static_cast<std::uint64_t>(d);
      if (c < 3) sq_rgb += static_cast<std::uint64_t>(d * d);
      m = std::max(m, d);
    }
    r.max_channel_diff = std::max(r.max_channel_diff, m);
    if (m > options.max_channel) ++r.pixels_over;
  }
  r.mean_abs_diff = double(sum) / (4.0 * double(r.pixel_count));
  r.fraction_over = double(r.pixels_over) / double(r.pixel_count);
  const double mse = double(sq_rgb) / (3.0 * double(r.pixel_count));
  r.psnr_db = mse == 0.0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(255.0 * 255.0 / mse);
  r.passed = r.fraction_over <= options.max_fraction;
  return r;
}

double ssim(const Image& a, const Image& b) {
  check_pair(a, b);
  const int w = a.width, h = a.height;
  // Summed-area tables of x, y, x², y², xy (luma), so every window costs O(1).
  const std::size_t W = std::size_t(w) + 1;
  std::vector<double> sx(W * (h + 1)), sy(sx.size()), sxx(sx.size()), syy(sx.size()), sxy(sx.size());
  auto luma = [](const std::uint8_t* p) { return 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2]; };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double u = luma(a.pixel(x, y)), v = luma(b.pixel(x, y));
      const std::size_t i = std::size_t(y + 1) * W + std::size_t(x + 1), up = i - W, left = i - 1, diag = up - 1;
      sx[i] = u + sx[up] + sx[left] - sx[diag];
      sy[i] = v + sy[up] + sy[left] - sy[diag];
      sxx[i] = u * u + sxx[up] + sxx[left] - sxx[diag];
      syy[i] = v * v + syy[up] + syy[left] - syy[diag];
      sxy[i] = u * v + sxy[up] + sxy[left] - sxy[diag];
    }
  const int kw = std::min(8, w), kh = std::min(8, h);
  const double n = double(kw) * kh, c1 = (0.01 * 255) * (0.01 * 255), c2 = (0.03 * 255) * (0.03 * 255);
  auto box = [&](const std::vector<double>& t, int x0, int y0) {
    const std::size_t i0 = std::size_t(y0) * W + std::size_t(x0), i1 = std::size_t(y0 + kh) * W + std::size_t(x0 + kw);
    return t[i1] - t[std::size_t(y0) * W + std::size_t(x0 + kw)] - t[std::size_t(y0 + kh) * W + std::size_t(x0)] + t[i0];
  };
  double total = 0;
  std::int64_t windows = 0;
  for (int y = 0; y + kh <= h; ++y)
    for (int x = 0; x + kw <= w; ++x) {
      const double mx = box(sx, x, y) / n, my = box(sy, x, y) / n;
      const double vx = std::max(0.0, box(sxx, x, y) / n - mx * mx), vy = std::max(0.0, box(syy, x, y) / n - my * my);
      const double cxy = box(sxy, x, y) / n - mx * my;
      total += ((2 * mx * my + c1) * (2 * cxy + c2)) / ((mx * mx + my * my + c1) * (vx + vy + c2));
      ++windows;
    }
  return total / double(windows);
}

Image diff_heatmap(const Image& a, const Image& b) {
  check_pair(a, b);
  // One colour per possible difference, computed once.
  std::array<std::array<std::uint8_t, 3>, 256> lut{};
  lut[0] = {0, 0, 0};
  for (int d = 1; d < 256; ++d) lut[d] = inferno(0.25 + 0.75 * std::log(double(d)) / std::log(255.0));

  Image out(a.width, a.height);
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const auto& c = lut[pixel_max_diff(a.pixel(x, y), b.pixel(x, y))];
      std::uint8_t* o = out.pixel(x, y);
      o[0] = c[0];
      o[1] = c[1];
      o[2] = c[2];
      o[3] = 255;
    }
  return out;
}

}  // namespace grainflow::render
