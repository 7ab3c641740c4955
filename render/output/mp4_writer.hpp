// H.264 MP4 encoding of RGBA8 frames with libx264 through FFmpeg (libavcodec, libavformat,
// libswscale): yuv420p, BT.709 tagged, odd sizes padded to even, written atomically
// (SPEC.md §3, "Outputs": H.264 MP4).
#pragma once
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "render/image/image.hpp"

namespace grainflow::render {

struct Mp4Options {
  int fps = 30;  // constant frame rate; frame k is shown at k / fps seconds
  int crf = 20;  // x264 constant rate factor, 0 (lossless) .. 51; 18-23 looks clean
  // x264 preset. superfast: ~50 ms CPU per 1920x1080 frame (crf 20, 2 threads), so ~40
  // frames/s on this 2-core machine when idle and 20 frames/s on one core; veryfast needs
  // ~86 ms (<= ~23 frames/s with both cores, nothing left for the simulation) for files
  // ~40% smaller; ultrafast ~26 ms but files 1.5x larger than superfast's. Figures from
  // tests/bench/bench_encode.cpp.
  std::string preset = "superfast";
  int threads = 2;  // encoder threads; the machine is shared, the renderer needs a core
};

// Throws grainflow::Error naming `path`, the option, its value and what is allowed, or
// the missing libx264 encoder. Mp4Writer calls it; sinks call it early to fail fast.
void check_mp4_options(const std::filesystem::path& path, const Mp4Options& options);

// Encodes frames of one fixed size into `path`. The file appears under `path` only after
// finish(); before that it lives under a temporary name in the same directory, and the
// destructor removes it if finish() was not reached.
class Mp4Writer {
public:
  // Width and height are the frame size; odd values are padded to even by repeating the
  // last column/row (yuv420p needs even sizes). Throws grainflow::Error if libx264 is not
  // available, an option is out of range, or the file cannot be created.
  Mp4Writer(std::filesystem::path path, int width, int height, Mp4Options options = {});
  ~Mp4Writer();
  Mp4Writer(const Mp4Writer&) = delete;
  Mp4Writer& operator=(const Mp4Writer&) = delete;

  // Frame size must match the constructor's. Throws grainflow::Error on encoder/IO errors.
  void write(const Image& frame);
  // Flushes the encoder, writes the index (moved to the front: +faststart) and renames
  // the file into place. Further write()/finish() calls are errors.
  void finish();

  std::int64_t frames_written() const;
  int encoded_width() const;   // padded to even
  int encoded_height() const;  // padded to even

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace grainflow::render
