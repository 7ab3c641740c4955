#include "scenes/src/run/run_folder.hpp"

#include <system_error>

#include "engine/io/atomic_file.hpp"
#include "engine/core/error.hpp"

namespace grainflow::scenes {

namespace fs = std::filesystem;

const std::vector<std::string_view>& RunFolder::result_files() {
  static const std::vector<std::string_view> names = {"scene.toml", "run.json", "stats.csv", "stats.csv.partial"};
  return names;
}

namespace {

std::string listing(const fs::path& dir) {
  std::string s;
  int n = 0;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (n == 4) {
      s += ", …";
      break;
    }
    s += (n++ ? ", " : "") + e.path().filename().string() + (e.is_directory(ec) ? "/" : "");
  }
  return s;
}

void remove_previous_results(const fs::path& dir) {
  std::error_code ec;
  for (auto name : RunFolder::result_files()) fs::remove(dir / fs::path(name), ec);
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (e.path().extension() == ".mp4" && e.is_regular_file(ec)) fs::remove(e.path(), ec);
  }
  const fs::path frames = dir / "frames";
  if (fs::is_directory(frames, ec))
    for (const auto& e : fs::directory_iterator(frames, ec))
      if (e.is_regular_file(ec)) fs::remove(e.path(), ec);
}

}  // namespace

RunFolder RunFolder::open(const fs::path& dir, RunFolderMode mode) {
  if (dir.empty()) throw Error("run folder: empty path; allowed: -o DIR with a directory path");
  std::error_code ec;
  const fs::file_status st = fs::status(dir, ec);
  const bool exists = fs::exists(st);
  if (exists && !fs::is_directory(st))
    throw Error("run folder '" + dir.string() + "' exists and is not a directory; allowed: a new or empty directory");

  if (exists) {
    const bool empty = fs::is_empty(dir, ec);
    if (ec) throw Error("cannot read run folder '" + dir.string() + "': " + ec.message());
    switch (mode) {
      case RunFolderMode::Fresh:
        if (!empty)
          throw Error("run folder '" + dir.string() + "' is not empty (holds " + listing(dir) +
                      "); allowed: a new or empty folder, or --force to replace the previous run's output");
        break;
      case RunFolderMode::Force: remove_previous_results(dir); break;
      case RunFolderMode::Resume:
        if (!fs::exists(dir / "run.json", ec))
          throw Error("cannot resume in '" + dir.string() + "': it holds no run.json from a previous run");
        break;
    }
  } else if (mode == RunFolderMode::Resume) {
    throw Error("cannot resume in '" + dir.string() + "': no such folder");
  }

  fs::create_directories(dir / "frames", ec);
  if (ec) throw Error("cannot create run folder '" + (dir / "frames").string() + "': " + ec.message());
  // An existing folder may still be read-only; find out now, not after hours of simulation.
  try {
    io::AtomicFile probe(dir / ".grainflow-write-test");
    probe.abort();
  } catch (const Error& e) {
    throw Error("run folder '" + dir.string() + "' is not writable (" + e.what() + ")");
  }
  return RunFolder(dir);
}

}  // namespace grainflow::scenes
