#include "scenes/src/run/run_folder.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <utility>
#include <algorithm>
#include <regex>
#include <system_error>

#include "engine/core/error.hpp"
#include "engine/io/atomic_file.hpp"

namespace grainflow::scenes {

namespace fs = std::filesystem;

namespace {

// What DIR holds, for an error message: the first few names, leaving out the lock file
// this run has just taken there (the user never put it there, and it goes with the error).
std::string listing(const fs::path& dir) {
  std::string s;
  int n = 0;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (e.path().filename() == RunFolder::kLock) continue;
    if (n == 4) {
      s += ", …";
      break;
    }
    s += (n++ ? ", " : "") + e.path().filename().string() + (e.is_directory(ec) ? "/" : "");
  }
  return s;
}

// A claim names a file in DIR or one folder below it, never outside: the manifest is
// read back from disk and distrusted like any input. Any file name is fine (a scene may be
// called "Düne 2.toml") but for line breaks, which the one-name-a-line list cannot hold.
bool valid_claim(std::string_view name) {
  if (name.empty() || name.size() > 255 || name.front() == '/') return false;
  if (name.find_first_of(std::string_view("\n\r\0", 3)) != std::string_view::npos) return false;
  int parts = 0;
  for (std::size_t a = 0; a <= name.size(); ++parts) {
    const std::size_t b = std::min(name.find('/', a), name.size());
    const std::string_view part = name.substr(a, b - a);
    if (part.empty() || part == "." || part == "..") return false;
    a = b + 1;
  }
  return parts <= 2;
}

// Removes a claimed file with what its writers leave beside it: `<name>.partial`
// (stats.csv while running), `<name>.partial.resuming` (an MP4 being resumed) and
// AtomicFile temporaries `<name>.tmp-<pid>-<n>`.
void remove_claimed(const fs::path& dir, const std::string& name) {
  std::error_code ec;
  // A claim one folder down is removed only through a real folder of DIR: were that folder
  // replaced by a link, removing through it would delete files outside the run folder.
  if (const std::size_t slash = name.find('/'); slash != std::string::npos) {
    const fs::file_status st = fs::symlink_status(dir / name.substr(0, slash), ec);
    if (ec || !fs::is_directory(st)) return;
  }
  // A numbered series, "FOLDER/PREFIX*SUFFIX" (kFrameFiles, the field files): every
  // PREFIX<6 or more digits>SUFFIX in FOLDER, with its AtomicFile temporaries; nothing else.
  if (const std::size_t star = name.find('*'); star != std::string::npos) {
    const std::size_t slash = name.rfind('/', star);
    const std::string folder = slash == std::string::npos ? std::string() : name.substr(0, slash);
    const std::string prefix = name.substr(slash == std::string::npos ? 0 : slash + 1, star - (slash + 1));
    const std::string suffix = name.substr(star + 1);
    auto quote = [](const std::string& t) {
      std::string q;
      for (char c : t) {
        if (std::string_view(R"(\^$.|?*+()[]{}-)").find(c) != std::string_view::npos) q += '\\';
        q += c;
      }
      return q;
    };
    const std::regex numbered("^" + quote(prefix) + "[0-9]{6,}" + quote(suffix) + R"((\.tmp-[0-9]+-[0-9]+)?$)");
    for (const auto& e : fs::directory_iterator(dir / folder, ec))
      if (e.is_regular_file(ec) && std::regex_match(e.path().filename().string(), numbered)) fs::remove(e.path(), ec);
    if (!folder.empty()) fs::remove(dir / folder, ec);  // only when nothing else is left in it
    return;
  }
  const fs::path p = dir / name;
  fs::remove(p, ec);
  fs::path partial = p;
  partial += ".partial";
  fs::remove(partial, ec);
  partial += ".resuming";  // an MP4 resume killed while it copied the kept frames
  fs::remove(partial, ec);
  const std::string tmp_prefix = p.filename().string() + ".tmp-";
  for (const auto& e : fs::directory_iterator(p.parent_path(), ec))
    if (e.is_regular_file(ec) && e.path().filename().string().rfind(tmp_prefix, 0) == 0) fs::remove(e.path(), ec);
}

// The claims of the previous run in DIR: the names its manifest lists. Throws when the
// manifest is unreadable or lists a name outside DIR.
std::vector<std::string> read_manifest(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error("cannot read '" + file.string() + "'");
  std::vector<std::string> names;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (!valid_claim(line) || names.size() > 1000)
      throw Error("'" + file.string() + "' is not a grainflow file list (it names '" + line.substr(0, 80) +
                  "'); nothing was removed; allowed: remove the folder's contents yourself or choose another folder");
    names.push_back(line);
  }
  return names;
}

}  // namespace

RunFolder RunFolder::open(const fs::path& dir, RunFolderMode mode) {
  if (dir.empty()) throw Error("run folder: empty path; allowed: -o DIR with a directory path");
  std::error_code ec;
  const fs::file_status st = fs::status(dir, ec);
  const bool exists = fs::exists(st);
  if (exists && !fs::is_directory(st))
    throw Error("run folder '" + dir.string() + "' exists and is not a directory; allowed: a new or empty directory");

  RunFolder folder(dir);
  if (exists) {
    const bool empty = fs::is_empty(dir, ec);
    if (ec) throw Error("cannot read run folder '" + dir.string() + "': " + ec.message());
    // Before --force removes anything or --resume reads anything.
    if (mode != RunFolderMode::Fresh && !empty) folder.lock();
    struct DropLock {  // a refused folder keeps no lock file of ours
      RunFolder& f;
      bool armed = true;
      ~DropLock() {
        std::error_code e;
        if (armed && f.created_lock_) fs::remove(f.dir_ / kLock, e);
      }
    } drop{folder};
    switch (mode) {
      case RunFolderMode::Fresh:
        if (!empty)
          throw Error("run folder '" + dir.string() + "' is not empty (holds " + listing(dir) +
                      "); allowed: a new or empty folder, or --force to replace the previous run's output");
        break;
      case RunFolderMode::Force:
        if (empty) break;
        if (!fs::exists(dir / kManifest, ec))
          throw Error("run folder '" + dir.string() + "' holds no grainflow run (no " + std::string(kManifest) +
                      "; it holds " + listing(dir) + "), so --force removes nothing there; allowed: a new or empty "
                      "folder, or one a grainflow run or render wrote");
        for (const auto& name : read_manifest(dir / kManifest)) remove_claimed(dir, name);
        fs::remove(dir / kManifest, ec);
        break;
      case RunFolderMode::Resume:
        if (!fs::exists(dir / "run.json", ec) || !fs::exists(dir / kManifest, ec))
          throw Error("cannot resume in '" + dir.string() + "': it holds no run of grainflow (no run.json or " +
                      std::string(kManifest) + ")");
        // Further claims add to the previous run's.
        folder.claimed_ = read_manifest(dir / kManifest);
        folder.resumed_ = true;
        break;
    }
    drop.armed = false;
  } else if (mode == RunFolderMode::Resume) {
    throw Error("cannot resume in '" + dir.string() + "': no such folder");
  }

  folder.created_dir_ = !exists;
  if (folder.lock_fd_ < 0) {
    fs::create_directories(dir, ec);
    if (ec) throw Error("cannot create run folder '" + dir.string() + "': " + ec.message());
    folder.lock();
  }
  folder.created_frames_ = !fs::exists(fs::symlink_status(dir / "frames", ec));
  try {
    io::make_output_folder(dir / "frames");
  } catch (const Error&) {
    folder.abandon();
    throw;
  }
  // An existing folder may still be read-only; find out now, not after hours of simulation.
  try {
    io::AtomicFile probe(dir / ".grainflow-write-test");
    probe.abort();
  } catch (const Error& e) {
    folder.abandon();
    throw Error("run folder '" + dir.string() + "' is not writable (" + e.what() + ")");
  }
  if (mode != RunFolderMode::Resume) folder.write_manifest();
  return folder;
}

void RunFolder::lock() {
  const fs::path file = dir_ / kLock;
  const bool existed = fs::exists(file);
  lock_fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ < 0)
    throw Error("run folder '" + dir_.string() + "' is not writable (" + file.string() + ": " + std::strerror(errno) + ")");
  created_lock_ = !existed;
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(lock_fd_);
    lock_fd_ = -1;
    throw Error("run folder '" + dir_.string() + "' is in use by another grainflow process (its run or render is "
                "still going); allowed: wait for it, stop it (Ctrl-C writes a checkpoint), or choose another folder");
  }
}

RunFolder::RunFolder(RunFolder&& o) noexcept
    : dir_(std::move(o.dir_)), claimed_(std::move(o.claimed_)), created_dir_(o.created_dir_),
      created_frames_(o.created_frames_), resumed_(o.resumed_), created_lock_(o.created_lock_),
      lock_fd_(std::exchange(o.lock_fd_, -1)) {}

RunFolder::~RunFolder() {
  // Closing releases the lock (so does the kernel when a killed process's files close).
  if (lock_fd_ >= 0) ::close(lock_fd_);
}

void RunFolder::claim(std::string_view name) {
  if (!valid_claim(name))
    throw Error("cannot write '" + std::string(name) + "' in run folder '" + dir_.string() +
                "': allowed: a file name without line breaks, in the folder or one folder below it");
  for (const auto& c : claimed_)
    if (c == name) return;
  claimed_.emplace_back(name);
  write_manifest();
}

void RunFolder::write_manifest() const {
  std::string text = "# Files grainflow wrote in this folder; --force removes exactly these (and their temporaries).\n";
  for (const auto& c : claimed_) text += c + "\n";
  io::write_text_atomically(dir_ / kManifest, text);
}

void RunFolder::abandon() noexcept {
  // A resume that failed to start leaves the previous run's files as they were.
  if (resumed_) return;
  std::error_code ec;
  for (const auto& name : claimed_) remove_claimed(dir_, name);
  claimed_.clear();
  fs::remove(dir_ / kManifest, ec);
  if (created_lock_) fs::remove(dir_ / kLock, ec);
  if (created_frames_) fs::remove(dir_ / "frames", ec);  // only when empty
  if (created_dir_) fs::remove(dir_, ec);
}

}  // namespace grainflow::scenes
