#include "render/output/png_sequence_sink.hpp"

#include <cstdio>
#include <system_error>
#include <utility>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"

namespace grainflow::render {

PngSequenceSink::PngSequenceSink(std::filesystem::path directory, PngOptions options)
    : directory_(std::move(directory)), options_(options) {
  io::make_output_folder(directory_);
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
