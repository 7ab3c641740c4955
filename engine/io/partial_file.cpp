#include "engine/io/partial_file.hpp"

#include <cerrno>
#include <cstring>
#include <string>
#include <utility>

#include "engine/core/error.hpp"

namespace grainflow::io {

namespace fs = std::filesystem;

PartialFile::PartialFile(fs::path final_path, const char* mode) : final_(std::move(final_path)) {
  partial_ = final_;
  partial_ += ".partial";
  file_ = std::fopen(partial_.c_str(), mode);
  if (!file_) throw Error("cannot create '" + partial_.string() + "': " + std::strerror(errno));
}

PartialFile PartialFile::create(fs::path final_path) { return PartialFile(std::move(final_path), "wb"); }

PartialFile PartialFile::resume(fs::path final_path, std::uint64_t size) {
  fs::path partial = final_path;
  partial += ".partial";
  std::error_code ec;
  if (!fs::exists(partial, ec)) {
    if (!fs::exists(final_path, ec))
      throw Error("cannot continue '" + final_path.string() + "': neither it nor its .partial exists");
    fs::rename(final_path, partial, ec);
    if (ec) throw Error("cannot continue '" + final_path.string() + "': " + ec.message());
  }
  const std::uintmax_t have = fs::file_size(partial, ec);
  if (ec) throw Error("cannot continue '" + partial.string() + "': " + ec.message());
  if (have < size)
    throw Error("cannot continue '" + partial.string() + "': it holds " + std::to_string(have) +
                " bytes, the checkpoint saw " + std::to_string(size));
  // What was written after the checkpoint is written again by the resumed run.
  fs::resize_file(partial, size, ec);
  if (ec) throw Error("cannot continue '" + partial.string() + "': " + ec.message());
  PartialFile f(std::move(final_path), "ab");
  f.size_ = size;
  return f;
}

PartialFile::PartialFile(PartialFile&& o) noexcept
    : final_(std::move(o.final_)), partial_(std::move(o.partial_)), file_(std::exchange(o.file_, nullptr)),
      size_(o.size_), finished_(o.finished_) {}

PartialFile& PartialFile::operator=(PartialFile&& o) noexcept {
  if (this != &o) {
    if (file_) std::fclose(file_);
    final_ = std::move(o.final_);
    partial_ = std::move(o.partial_);
    file_ = std::exchange(o.file_, nullptr);
    size_ = o.size_;
    finished_ = o.finished_;
  }
  return *this;
}

PartialFile::~PartialFile() {
  if (file_) std::fclose(file_);
}

void PartialFile::fail(const char* what) const {
  throw Error(std::string("cannot ") + what + " '" + partial_.string() + "': " + std::strerror(errno));
}

void PartialFile::write(std::string_view bytes) {
  if (!file_) throw Error("'" + partial_.string() + "' is closed");
  if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size()) fail("write");
  size_ += bytes.size();
}

void PartialFile::flush() {
  if (file_ && std::fflush(file_) != 0) fail("write");
}

void PartialFile::finish() {
  if (finished_) return;
  flush();
  const int rc = std::fclose(file_);
  file_ = nullptr;
  if (rc != 0) fail("write");
  std::error_code ec;
  fs::rename(partial_, final_, ec);
  if (ec) throw Error("cannot rename '" + partial_.string() + "' to '" + final_.string() + "': " + ec.message());
  finished_ = true;
}

}  // namespace grainflow::io
