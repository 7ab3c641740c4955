#include "engine/io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <utility>

#include "engine/core/error.hpp"

namespace grainflow::io {

namespace {

// Two AtomicFiles for the same target in one process (e.g. two threads) must not share a
// temporary name, so the pid is followed by a process-wide counter.
std::atomic<unsigned long> g_counter{0};

std::string os_reason(int err) { return std::strerror(err); }

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path final_path) : final_(std::move(final_path)) {
  if (final_.empty()) throw Error("output file: empty path");
  if (!final_.has_filename()) throw Error("output file '" + final_.string() + "': path names a directory, a file is needed");
  temp_ = final_;
  temp_ += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(g_counter.fetch_add(1));
  // Create the file now so an unwritable or missing directory is reported before any
  // expensive work, with the path the user gave.
  const int fd = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) {
    const int err = errno;
    throw Error("cannot create output file '" + final_.string() + "' (temporary '" + temp_.string() +
                "'): " + os_reason(err));
  }
  ::close(fd);
  active_ = true;
}

AtomicFile::~AtomicFile() { abort(); }

AtomicFile::AtomicFile(AtomicFile&& other) noexcept
    : final_(std::move(other.final_)), temp_(std::move(other.temp_)), committed_(other.committed_),
      active_(other.active_) {
  other.active_ = false;
}

AtomicFile& AtomicFile::operator=(AtomicFile&& other) noexcept {
  if (this != &other) {
    abort();
    final_ = std::move(other.final_);
    temp_ = std::move(other.temp_);
    committed_ = other.committed_;
    active_ = other.active_;
    other.active_ = false;
  }
  return *this;
}

void AtomicFile::commit() {
  if (!active_) throw Error("output file '" + final_.string() + "': commit() on a file already committed or aborted");
  if (std::rename(temp_.c_str(), final_.c_str()) != 0) {
    const int err = errno;
    throw Error("cannot rename '" + temp_.string() + "' to '" + final_.string() + "': " + os_reason(err));
  }
  active_ = false;
  committed_ = true;
}

void AtomicFile::abort() noexcept {
  if (!active_) return;
  ::unlink(temp_.c_str());
  active_ = false;
}

void write_text_atomically(const std::filesystem::path& path, std::string_view text) {
  AtomicFile file(path);
  std::FILE* out = std::fopen(file.path().c_str(), "wb");
  if (!out) throw Error("cannot write '" + path.string() + "': " + os_reason(errno));
  // stdio reports a full disk at fwrite, fflush or fclose, whichever writes the block.
  const bool written = std::fwrite(text.data(), 1, text.size(), out) == text.size() && std::fflush(out) == 0;
  const int err = errno;
  const bool closed = std::fclose(out) == 0;
  if (!written || !closed) throw Error("cannot write '" + path.string() + "': " + os_reason(written ? errno : err));
  file.commit();
}

void make_output_folder(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(path, ec);
  if (fs::is_symlink(st))
    throw Error("output folder '" + path.string() + "' is a link; grainflow writes only into folders of its own, "
                "never through a link; allowed: remove the link or choose another run folder");
  if (fs::exists(st) && !fs::is_directory(st))
    throw Error("output folder '" + path.string() + "' exists and is not a folder; allowed: remove it or choose "
                "another run folder");
  fs::create_directories(path, ec);
  if (ec) throw Error("cannot create output folder '" + path.string() + "': " + ec.message());
}

}  // namespace grainflow::io
