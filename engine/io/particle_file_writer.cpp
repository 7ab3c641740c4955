#include "engine/io/particle_file_writer.hpp"

#include <fmt/format.h>

#include <iterator>

#include "engine/core/error.hpp"

namespace grainflow::io {

void append_real(std::string& out, double v, Precision p) {
  // fmt's "{}" is the shortest round-trip form of the type it is given.
  if (p == Precision::float32) fmt::format_to(std::back_inserter(out), "{}", static_cast<float>(v));
  else fmt::format_to(std::back_inserter(out), "{}", v);
}

std::vector<ExtraColumn> extra_columns(const ParticleFrame& f) {
  std::vector<ExtraColumn> out;
  const auto& e = f.extra;
  for (std::size_t k = 0; k < e.size();) {
    // The base B of a vector starting at column k, if columns k..k+2 are B?x, B?y, B?z.
    auto base = [&](std::size_t j, char axis) -> std::string_view {
      const std::string& n = e[j].first;
      if (n.size() < 2 || n.back() != axis) return {};
      std::string_view b(n.data(), n.size() - 1);
      if (b.size() >= 2 && b.back() == '_') b.remove_suffix(1);
      return b;
    };
    if (k + 2 < e.size()) {
      const std::string_view b = base(k, 'x');
      if (!b.empty() && base(k + 1, 'y') == b && base(k + 2, 'z') == b &&
          e[k + 1].first.size() == e[k].first.size() && e[k + 2].first.size() == e[k].first.size()) {
        out.push_back({std::string(b), 3, {&e[k].second, &e[k + 1].second, &e[k + 2].second}});
        k += 3;
        continue;
      }
    }
    out.push_back({e[k].first, 1, {&e[k].second, nullptr, nullptr}});
    ++k;
  }
  return out;
}

ParticleFileWriter::ParticleFileWriter(const std::string& path, Precision precision)
    : file_(PartialFile::create(path)), precision_(precision) {}

ParticleFileWriter::ParticleFileWriter(const std::string& path, Precision precision, std::uint64_t resume_size,
                                       int resume_frames)
    : file_(PartialFile::resume(path, resume_size)), precision_(precision), frames_(resume_frames) {}

void ParticleFileWriter::write(const ParticleFrame& frame, std::int64_t step) {
  if (file_.finished()) throw Error(file_.final_path().string() + ": particle file written after close()");
  buf_.clear();
  format(buf_, frame, step);
  file_.write(buf_);
  ++frames_;
}

std::uint64_t ParticleFileWriter::flush() {
  file_.flush();
  return file_.size();
}

void ParticleFileWriter::close() { file_.finish(); }

}  // namespace grainflow::io
