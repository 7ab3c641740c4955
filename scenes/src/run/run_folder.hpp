// The output folder of one run (SPEC.md §3b): DIR/ with frames/, scene.toml, stats.csv,
// run.json, the MP4. Created before any work, so a bad or occupied path fails at once, and
// never silently overwritten: an existing non-empty folder needs --force (or a resume).
#pragma once
#include <filesystem>
#include <string_view>
#include <vector>

namespace grainflow::scenes {

enum class RunFolderMode {
  Fresh,   // DIR must be absent or empty
  Force,   // DIR may hold a previous run: its frames/ and result files are removed first
  Resume,  // DIR must hold a previous run (run.json); nothing is removed
};

class RunFolder {
public:
  // Creates DIR and DIR/frames/ (with parents) and checks DIR is writable. Throws
  // grainflow::Error naming the path, what is wrong and what is allowed.
  static RunFolder open(const std::filesystem::path& dir, RunFolderMode mode);

  const std::filesystem::path& dir() const { return dir_; }
  std::filesystem::path frames_dir() const { return dir_ / "frames"; }
  std::filesystem::path file(std::string_view name) const { return dir_ / std::filesystem::path(name); }

  // Result files a previous run leaves at the top of DIR; --force removes these (and the
  // files in frames/) so no stale output mixes with the new run. Other files are kept.
  static const std::vector<std::string_view>& result_files();

private:
  explicit RunFolder(std::filesystem::path dir) : dir_(std::move(dir)) {}
  std::filesystem::path dir_;
};

}  // namespace grainflow::scenes
