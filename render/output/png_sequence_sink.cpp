#include "render/output/png_sequence_sink.hpp"

#include <cstdio>
#include <system_error>
#include <utility>

#include "engine/core/error.hpp"

namespace grainflow::render {

PngSequenceSink::PngSequenceSink(std::filesystem::path directory, PngOptions options)
    : directory_(std::move(directory)), options_(options) {
  std::error_code ec;
  std::filesystem::create_directories(directory_, ec);
  if (ec) throw Error("cannot create frame directory '" + directory_.string() + "': " + ec.message());
  if (!std::filesystem::is_directory(directory_))
    throw Error("frame directory '" + directory_.string() + "' exists but is not a directory");
}

std::filesystem::path PngSequenceSink::frame_path(std::int64_t index) const {
  char name[40];
  std::snprintf(name, sizeof(name), "frame_%06lld.png", static_cast<long long>(index));
  return directory_ / name;
}

void PngSequenceSink::consume(const Image& frame, std::int64_t index, double /*time*/) {
  if (index < 0) throw Error("PNG sequence '" + directory_.string() + "': negative frame index " + std::to_string(index));
  write_png(frame_path(index), frame, options_);
  ++frames_written_;
}

}  // namespace grainflow::render
