// The output folder of one run or render (SPEC.md §3b): DIR/ with frames/, scene.toml,
// stats.csv, run.json, the MP4. Never silently overwritten, and safe to point anywhere:
// every file grainflow writes there is first claimed in DIR/.grainflow-files (written
// before the file exists, so it also covers a killed run), and --force removes exactly the
// claimed files of the previous run — nothing a user put there.
#pragma once
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "scenes/src/outputs/run_output.hpp"

namespace grainflow::scenes {

enum class RunFolderMode {
  Fresh,   // DIR must be absent or empty
  Force,   // DIR may hold a previous grainflow run: the files it claimed are removed first
  Resume,  // DIR must hold a previous run (run.json, manifest); nothing is removed
};

class RunFolder {
public:
  // The manifest of claimed files, one relative name a line.
  static constexpr std::string_view kManifest = ".grainflow-files";
  // Held (flock) by the process writing in DIR, so a second run, render, --force or
  // --resume in the same folder is refused instead of writing over a live run. The kernel
  // releases it when the process ends, however it ends. Never claimed: --force keeps it.
  static constexpr std::string_view kLock = ".grainflow-lock";

  // Creates DIR and DIR/frames/ (with parents) and checks DIR is writable. Force refuses
  // a non-empty DIR without a manifest ("holds no grainflow run"). Throws grainflow::Error
  // naming the path, what is wrong and what is allowed.
  static RunFolder open(const std::filesystem::path& dir, RunFolderMode mode);

  const std::filesystem::path& dir() const { return dir_; }
  std::filesystem::path frames_dir() const { return dir_ / "frames"; }
  std::filesystem::path file(std::string_view name) const { return dir_ / std::filesystem::path(name); }

  // Records that grainflow writes `name` (relative to DIR, or kFrameFiles), rewriting the
  // manifest atomically at once. Throws grainflow::Error for a name outside DIR.
  void claim(std::string_view name);
  const std::vector<std::string>& claimed() const { return claimed_; }

  // For a start that failed before the first step: removes the claimed files, the
  // manifest, and DIR/frames and DIR where open() created them (when empty). Never throws.
  // After a Resume open it removes nothing: those files are the previous run's.
  void abandon() noexcept;

  RunFolder(RunFolder&& o) noexcept;
  RunFolder& operator=(RunFolder&&) = delete;
  ~RunFolder();

private:
  explicit RunFolder(std::filesystem::path dir) : dir_(std::move(dir)) {}
  void lock();  // throws grainflow::Error when another process holds DIR
  void write_manifest() const;
  std::filesystem::path dir_;
  std::vector<std::string> claimed_;
  bool created_dir_ = false, created_frames_ = false;
  bool resumed_ = false;  // Resume: the claims are the previous run's; abandon() keeps them
  bool created_lock_ = false;
  int lock_fd_ = -1;
};

}  // namespace grainflow::scenes
