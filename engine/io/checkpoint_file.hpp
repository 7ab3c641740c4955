// The checkpoint container: a versioned, checksummed file holding one archive
// (archive.hpp) and a few header fields, written atomically (AtomicFile: the whole file
// or nothing under its name). Layout, native byte order:
//   8 bytes magic "GFCKPT\r\n" (\r\n: a text-mode copy is caught, as in PNG)
//   u32 format version, u32 0
//   u64 header length, header: engine name, scene fingerprint, simulated time, frames,
//     sequence number
//   u64 payload length, payload (the engine's and the run's state)
//   u64 FNV-1a 64 of every byte before it
// read_checkpoint refuses a file with another magic or version, a wrong length or a wrong
// checksum, naming the reason; what the payload means is the caller's business.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace grainflow::io {

// 2: the DEM state carries the contact virial of its forces (the pressure tensor).
// 3: the ED disks are stored at a common epoch, with their bodies (radius, mass, spin)
//    apart.
// 4: the ED event records no longer hold the pair event's time when a crossing comes first.
inline constexpr std::uint32_t kCheckpointVersion = 4;

struct CheckpointInfo {
  std::string engine;                  // "ed", "dem"
  std::uint64_t scene_fingerprint = 0; // of the scene's physics (what a resume may not change)
  double time = 0.0;                   // simulated time of the state
  std::int64_t frames = 0;             // frames written before it
  std::uint64_t sequence = 0;          // 1, 2, …: the newest of several has the largest
};

struct Checkpoint {
  CheckpointInfo info;
  std::string payload;
};

// Throws grainflow::Error naming the file and the OS reason ("no space left on device").
void write_checkpoint(const std::filesystem::path& file, const CheckpointInfo& info, std::string_view payload);
// Throws grainflow::Error when the file is not a grainflow checkpoint, has another format
// version, is truncated or fails its checksum.
Checkpoint read_checkpoint(const std::filesystem::path& file);

}  // namespace grainflow::io
