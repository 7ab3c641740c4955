#include "engine/io/checkpoint_file.hpp"

#include <cerrno>
#include <cstring>
#include <cstdio>
#include <fstream>
#include <span>

#include "engine/core/error.hpp"
#include "engine/core/state_digest.hpp"
#include "engine/io/archive.hpp"
#include "engine/io/atomic_file.hpp"

namespace grainflow::io {
namespace {

constexpr char kMagic[8] = {'G', 'F', 'C', 'K', 'P', 'T', '\r', '\n'};
std::uint64_t checksum(std::string_view bytes) {
  core::StateDigest d;  // FNV-1a 64: ≈ 1 GB/s, a few % of writing a checkpoint
  d.add_bytes(std::as_bytes(std::span(bytes.data(), bytes.size())));
  return d.value();
}

}  // namespace

void write_checkpoint(const std::filesystem::path& file, const CheckpointInfo& info, std::string_view payload) {
  ArchiveWriter header;
  header.string(info.engine);
  header.pod(info.scene_fingerprint);
  header.pod(info.time);
  header.pod(info.frames);
  header.pod(info.sequence);
  // Everything before the payload; the payload is written from where it lies (a DEM
  // state is ~500 bytes a sphere: copying it again would cost more than writing it).
  ArchiveWriter prefix;
  prefix.pod(kMagic);
  prefix.pod(kCheckpointVersion);
  prefix.pod(std::uint32_t(0));
  prefix.string(header.bytes());
  prefix.pod(static_cast<std::uint64_t>(payload.size()));
  core::StateDigest sum;
  sum.add_bytes(std::as_bytes(std::span(prefix.bytes().data(), prefix.bytes().size())));
  sum.add_bytes(std::as_bytes(std::span(payload.data(), payload.size())));
  const std::uint64_t checksum_value = sum.value();

  AtomicFile af(file);
  {
    std::FILE* f = std::fopen(af.path().c_str(), "wb");
    if (!f) throw Error("cannot write checkpoint " + file.string() + ": " + std::strerror(errno));
    bool ok = std::fwrite(prefix.bytes().data(), 1, prefix.bytes().size(), f) == prefix.bytes().size() &&
              std::fwrite(payload.data(), 1, payload.size(), f) == payload.size() &&
              std::fwrite(&checksum_value, sizeof checksum_value, 1, f) == 1;
    ok = std::fflush(f) == 0 && ok;
    const int err = errno;
    ok = std::fclose(f) == 0 && ok;
    if (!ok) throw Error("cannot write checkpoint " + file.string() + ": " + std::strerror(err ? err : errno));
  }
  af.commit();
}

Checkpoint read_checkpoint(const std::filesystem::path& file) {
  const std::string what = "checkpoint " + file.string();
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) throw Error(what + " is a directory, not a file");
  std::ifstream is(file, std::ios::binary);
  if (!is) throw Error("cannot open " + what + ": " + std::strerror(errno));
  const std::string bytes((std::istreambuf_iterator<char>(is)), std::istreambuf_iterator<char>());
  if (is.bad()) throw Error("cannot read " + what + ": " + std::strerror(errno));
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw Error(file.string() + " is not a grainflow checkpoint (no GFCKPT signature)");
  if (bytes.size() < sizeof kMagic + 2 * sizeof(std::uint32_t) + sizeof(std::uint64_t))
    throw Error(what + " is truncated");
  // Everything before the trailing checksum, read in order; a cut file says "truncated"
  // (from the lengths) rather than just "checksum".
  const std::string_view body(bytes.data(), bytes.size() - sizeof(std::uint64_t));
  std::uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + body.size(), sizeof stored);
  ArchiveReader lengths(body, what);
  char magic[8];
  lengths.pod(magic);
  const auto version = lengths.get<std::uint32_t>();
  (void)lengths.get<std::uint32_t>();
  if (version != kCheckpointVersion)
    throw Error(what + " has format version " + std::to_string(version) + "; this grainflow reads version " +
                std::to_string(kCheckpointVersion) + " only");
  Checkpoint ck;
  const std::string header = lengths.string();
  ck.payload = lengths.string();
  if (!lengths.at_end()) throw Error(what + " is corrupt: " + std::to_string(lengths.left()) + " unexpected bytes before the checksum");
  if (checksum(body) != stored) throw Error(what + " fails its checksum: the file was damaged after it was written");
  ArchiveReader h(header, what);
  ck.info.engine = h.string();
  h.pod(ck.info.scene_fingerprint);
  h.pod(ck.info.time);
  h.pod(ck.info.frames);
  h.pod(ck.info.sequence);
  return ck;
}

}  // namespace grainflow::io
