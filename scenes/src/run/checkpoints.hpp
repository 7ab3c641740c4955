// The checkpoints of a run folder (`output.checkpoint_every`, SIGINT/SIGTERM, run.max_wall):
// DIR/checkpoints/checkpoint_0.gfck and checkpoint_1.gfck, written alternately, so the
// last two are kept and a checkpoint being written never replaces the only good one.
// Each is an io checkpoint file (versioned, checksummed, written atomically).
#pragma once
#include <cstdint>
#include <string>
#include <string_view>

#include "engine/io/checkpoint_file.hpp"

namespace grainflow::scenes {

class RunFolder;

class CheckpointStore {
public:
  explicit CheckpointStore(RunFolder& folder) : folder_(folder) {}

  // Writes the next checkpoint over the older of the two (claimed in the folder first);
  // info.sequence is set here. Throws grainflow::Error naming the file on a write error.
  void write(io::CheckpointInfo info, std::string_view payload);

  // The newest checkpoint that reads back intact and belongs to this scene and engine.
  // A damaged newest one is reported on stderr and the older one is used; throws
  // grainflow::Error with each file's reason when none can be used.
  io::Checkpoint read_latest(std::string_view engine, std::uint64_t scene_fingerprint);

private:
  RunFolder& folder_;
  std::uint64_t sequence_ = 0;  // of the last one written or read
};

}  // namespace grainflow::scenes
