// FrameSink writing one PNG per frame: DIR/frame_000000.png, DIR/frame_000001.png, ...
// (index zero-padded to 6 digits; more digits past 999999). Each file is atomic on its own
// (SPEC.md §3, "Outputs": PNG sequences).
#pragma once
#include <filesystem>
#include <string>

#include "render/output/frame_sink.hpp"
#include "render/output/png_io.hpp"

namespace grainflow::render {

class PngSequenceSink : public FrameSink {
public:
  // Creates `directory` (and its parents) now, so a bad path fails before the run starts.
  explicit PngSequenceSink(std::filesystem::path directory, PngOptions options = {});

  void consume(const Image& frame, std::int64_t index, double time) override;
  // Every frame is complete when consume() returns, so there is nothing left to finalise.
  void finish() override {}
  // Nothing either: write_png() renames each file into place before consume() returns. A
  // resumed run writes frames K, K+1, ... again under the same names (atomic replace).
  void sync() override {}

  std::filesystem::path frame_path(std::int64_t index) const;
  std::int64_t frames_written() const { return frames_written_; }

private:
  std::filesystem::path directory_;
  PngOptions options_;
  std::int64_t frames_written_ = 0;
};

}  // namespace grainflow::render
