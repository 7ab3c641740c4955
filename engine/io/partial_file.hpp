// A file that grows while a run goes on, under `<final>.partial` ("usable but not
// finished": stats.csv.partial, particles.xyz.partial, pair.csv.partial, the MP4's
// .partial), renamed to its final name by finish(). A killed run leaves the .partial with
// everything flushed so far; a resumed run (`grainflow run --resume`) continues it from the
// size its checkpoint recorded, cutting off what was written after the checkpoint.
#pragma once
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string_view>

namespace grainflow::io {

class PartialFile {
public:
  // Creates `<final>.partial` (replacing one a killed run left). Throws grainflow::Error
  // naming the file and the OS reason.
  static PartialFile create(std::filesystem::path final_path);
  // Continues the file a checkpointed run wrote: `<final>.partial`, else `<final>` itself
  // (the run was interrupted and finished it), cut to `size` bytes. Throws when neither
  // exists or the file is shorter than `size` (it does not hold what the checkpoint saw).
  static PartialFile resume(std::filesystem::path final_path, std::uint64_t size);

  PartialFile(PartialFile&& o) noexcept;
  PartialFile& operator=(PartialFile&& o) noexcept;
  PartialFile(const PartialFile&) = delete;
  PartialFile& operator=(const PartialFile&) = delete;
  ~PartialFile();  // closes; the .partial stays when finish() was not called

  // Throws grainflow::Error naming the file ("No space left on device").
  void write(std::string_view bytes);
  void flush();
  // Bytes written so far (after flush(): what a checkpoint records).
  std::uint64_t size() const { return size_; }
  // Flushes, closes and renames the .partial to the final name. Idempotent.
  void finish();
  bool finished() const { return finished_; }
  const std::filesystem::path& final_path() const { return final_; }
  const std::filesystem::path& partial_path() const { return partial_; }

private:
  PartialFile(std::filesystem::path final_path, const char* mode);
  [[noreturn]] void fail(const char* what) const;
  std::filesystem::path final_, partial_;
  std::FILE* file_ = nullptr;
  std::uint64_t size_ = 0;
  bool finished_ = false;
};

}  // namespace grainflow::io
