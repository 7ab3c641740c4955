// PNG files in and out (libpng): frames of a run, golden images, `grainflow diff` inputs.
// Writing is atomic (io::AtomicFile) and tuned for speed; reading accepts any PNG and
// converts it to the renderer's RGBA8 Image (SPEC.md §3, "Outputs").
#pragma once
#include <filesystem>
#include <utility>

#include "render/image/image.hpp"

namespace grainflow::render {

struct PngOptions {
  // zlib level 0..9. Level 1 without filters is ~10x faster than libpng's default
  // (level 6 + adaptive filters costs ~0.5 s per 1080p frame) for files ~1.5-2x larger.
  int compression_level = 1;
  // Per-row adaptive filtering (libpng's heuristic); off = filter type None on every row.
  bool filters = false;
};

// Writes `image` as 8-bit RGB when every alpha is 255, else 8-bit RGBA. Throws grainflow::Error naming the path and the reason
// (empty image, bad option, unwritable directory, disk full).
void write_png(const std::filesystem::path& path, const Image& image, const PngOptions& options = {});

// Reads any PNG (gray, gray+alpha, palette, RGB, RGBA; 1..16 bits; interlaced) as RGBA8.
// Sample values are taken as stored — no gamma conversion: 16-bit samples are scaled by
// 255/65535 with rounding, low-bit gray is expanded to the full 0..255 range, tRNS becomes
// alpha, missing alpha is 255. Throws grainflow::Error naming the path for a missing file,
// a file that is not a PNG, or a corrupt/truncated one.
Image read_png(const std::filesystem::path& path);

// Width and height from the PNG header alone (signature and IHDR, 24 bytes), without
// decoding: lets a caller refuse an image before reserving its pixels. Throws
// grainflow::Error like read_png for a missing or non-PNG file.
std::pair<int, int> png_size(const std::filesystem::path& path);

}  // namespace grainflow::render
