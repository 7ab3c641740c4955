// FrameSink writing an H.264 MP4 (Mp4Writer). The video size is taken from the first
// frame; the file appears under its final name only after finish(), and until then is a
// `.partial` that plays at every moment, kept when the run is killed (SPEC.md §3, #12).
// With Mp4Options::resume_frames = K > 0 it continues the .partial a killed run left
// (Mp4Writer): the first frame it consumes is frame K (index K), and its size must be the
// old video's; the old file is read and copied when that frame arrives.
#pragma once
#include <filesystem>
#include <memory>
#include <string>

#include "render/output/frame_sink.hpp"
#include "render/output/mp4_writer.hpp"

namespace grainflow::render {

class Mp4Sink : public FrameSink {
public:
  // Checks the options and that the directory exists now, so a bad configuration fails
  // before the run starts rather than at the first frame.
  explicit Mp4Sink(std::filesystem::path path, Mp4Options options = {});
  ~Mp4Sink() override;

  // Frames are shown at a constant rate in the order given; `time` is not used (the
  // video's clock is frame index / fps). Resumed at K, the first index must be K.
  void consume(const Image& frame, std::int64_t index, double time) override;
  // Mp4Writer::sync(). Before the first frame there is nothing to put on disk: the .partial
  // is then the one a resume at this frame count starts from (or none, at frame 0).
  void sync() override;
  // Throws grainflow::Error if no frame was given: an MP4 was asked for and none can be made.
  // After a failure, consume() and finish() throw the first error again.
  void finish() override;

  // Frames in the video, those kept by a resume included.
  std::int64_t frames_written() const;

private:
  std::filesystem::path path_;
  Mp4Options options_;
  std::unique_ptr<Mp4Writer> writer_;
  std::string error_;  // the writer's construction failed: its error, reported again
};

}  // namespace grainflow::render
