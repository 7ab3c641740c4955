// The project's image comparator: golden-image regression tests and `grainflow diff`
// (ARCHITECTURE.md, "Tests": per-pixel tolerance and allowed fraction; pbrt's imgtool and
// Magnum's (max, mean) thresholds are the models).
#pragma once
#include <cstdint>

#include "render/image/image.hpp"

namespace grainflow::render {

struct CompareOptions {
  // A pixel is "over tolerance" when its largest channel difference |a - b| over R, G, B
  // and A exceeds max_channel (0..255). 0 = any change counts.
  int max_channel = 0;
  // The comparison passes when the fraction of pixels over tolerance is <= max_fraction
  // (0..1). 0 = no pixel may exceed max_channel.
  double max_fraction = 0.0;
};

struct CompareResult {
  bool passed = false;
  int max_channel_diff = 0;          // largest |a - b| over all pixels and channels, 0..255
  double mean_abs_diff = 0.0;        // mean |a - b| over all pixels and all 4 channels, 0..255
  std::int64_t pixels_over = 0;      // pixels whose largest channel difference > max_channel
  std::int64_t pixel_count = 0;      // width * height
  double fraction_over = 0.0;        // pixels_over / pixel_count
  // Peak signal-to-noise ratio of R, G, B in dB, 10·log10(255² / MSE); +inf when equal.
  double psnr_db = 0.0;
};

// Compares two images of the same size. A size mismatch is not a degree of difference but
// a wrong input (the golden image is of another scene/size), so it throws grainflow::Error
// naming both sizes — `grainflow diff` turns that into exit status 2. So do out-of-range
// options and empty images.
CompareResult compare_images(const Image& a, const Image& b, const CompareOptions& options = {});

// Mean structural similarity (SSIM, Wang et al. 2004) of the two images' luma (BT.601
// weights of R, G, B): the SSIM of every 8 × 8 window (uniform weights; the whole image when
// smaller), averaged, with C1 = (0.01·255)², C2 = (0.03·255)². 1 for equal images, lower
// the less alike their local structure is. Throws grainflow::Error on a size mismatch.
double ssim(const Image& a, const Image& b);

// A heat map of the per-pixel largest channel difference d: black where d = 0, otherwise
// the inferno colour map at t = 0.25 + 0.75 * log(d) / log(255), so a one-level change is
// plainly visible (dark purple) and large differences are bright yellow. Opaque. Throws
// grainflow::Error on a size mismatch.
Image diff_heatmap(const Image& a, const Image& b);

}  // namespace grainflow::render
