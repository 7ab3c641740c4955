// Atomic output files: every writer in grainflow writes to a temporary name in the target's
// directory and renames it into place when complete, so a killed run never leaves a
// truncated file under a finished-looking name (ARCHITECTURE.md, "Errors").
#pragma once
#include <filesystem>
#include <string_view>

namespace grainflow::io {

// Owns a temporary path `<final>.tmp-<pid>-<n>` beside the final path. Write to path(),
// then commit() renames it over the final path (rename(2) is atomic within a directory).
// If commit() is never called, the destructor removes the temporary file.
class AtomicFile {
public:
  // Throws grainflow::Error if the final path's directory does not exist or is not
  // writable (checked by creating the temporary file), naming the path and the OS reason.
  explicit AtomicFile(std::filesystem::path final_path);
  ~AtomicFile();

  AtomicFile(AtomicFile&& other) noexcept;
  AtomicFile& operator=(AtomicFile&& other) noexcept;
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  const std::filesystem::path& path() const { return temp_; }
  const std::filesystem::path& final_path() const { return final_; }
  bool committed() const { return committed_; }

  // Renames the temporary file to the final path. Throws grainflow::Error on failure
  // (the temporary is then removed by the destructor). Calling it twice is an error.
  void commit();
  // Removes the temporary file now; the object is then inert.
  void abort() noexcept;

private:
  std::filesystem::path final_;
  std::filesystem::path temp_;
  bool committed_ = false;
  bool active_ = false;
};

// Writes `text` to `path` through an AtomicFile: the whole file or nothing. A failed write
// (a full disk) throws grainflow::Error naming the file and the OS reason ("no space left
// on device"), and leaves the previous file in place.
void write_text_atomically(const std::filesystem::path& path, std::string_view text);

// Creates the folder `path` (with parents) for output files, or accepts it when it is
// already a real folder. A link there (or any other file) is refused with a
// grainflow::Error: files written through a link would land in — and overwrite — a folder
// the run does not own. Every output subfolder (frames/, fields/, checkpoints/) goes
// through here.
void make_output_folder(const std::filesystem::path& path);

}  // namespace grainflow::io
