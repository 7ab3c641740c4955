#include "render/output/mp4_sink.hpp"

#include <system_error>
#include <utility>

#include "engine/core/error.hpp"

namespace grainflow::render {

Mp4Sink::Mp4Sink(std::filesystem::path path, Mp4Options options)
    : path_(std::move(path)), options_(std::move(options)) {
  check_mp4_options(path_, options_);
  const std::filesystem::path dir = path_.has_parent_path() ? path_.parent_path() : std::filesystem::path(".");
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    throw Error("MP4 '" + path_.string() + "': directory '" + dir.string() + "' does not exist");
}

Mp4Sink::~Mp4Sink() = default;

void Mp4Sink::consume(const Image& frame, std::int64_t index, double /*time*/) {
  if (!error_.empty()) throw Error(error_);
  if (!writer_) {
    if (options_.resume_frames > 0 && index != options_.resume_frames) {
      error_ = "MP4 '" + path_.string() + "': resumed after frame " + std::to_string(options_.resume_frames - 1) +
               ", so the first frame must be frame " + std::to_string(options_.resume_frames) + ", not " +
               std::to_string(index);
      throw Error(error_);
    }
    // A writer that failed to open would fail again at the next frame, perhaps for a new
    // reason (its .partial half made); the first cause is the one to report.
    try {
      writer_ = std::make_unique<Mp4Writer>(path_, frame.width, frame.height, options_);
    } catch (const Error& e) {
      error_ = e.what();
      throw;
    }
  }
  writer_->write(frame);
}

void Mp4Sink::finish() {
  if (!error_.empty()) throw Error(error_);
  if (!writer_) throw Error("MP4 '" + path_.string() + "': no frames were rendered, so there is no video to write");
  writer_->finish();
}

void Mp4Sink::sync() {
  if (!error_.empty()) throw Error(error_);
  if (writer_) writer_->sync();
}

std::int64_t Mp4Sink::frames_written() const {
  return writer_ ? writer_->frames_written() : options_.resume_frames;
}

}  // namespace grainflow::render
