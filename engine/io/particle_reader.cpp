#include "engine/io/particle_reader.hpp"

#include "engine/core/error.hpp"
#include "engine/io/lammps_dump_reader.hpp"
#include "engine/io/line_reader.hpp"
#include "engine/io/xyz_reader.hpp"

namespace grainflow::io {
namespace {

bool gzip_magic(std::string_view s) {
  return s.size() >= 2 && static_cast<unsigned char>(s[0]) == 0x1f && static_cast<unsigned char>(s[1]) == 0x8b;
}

}  // namespace

std::unique_ptr<ParticleReader> open_particle_file(const std::string& path) {
  // One open file for the probe and the reader: a pipe (`render <(gunzip -c dump.gz)`)
  // cannot be opened a second time from its start.
  LineReader in(path);
  std::string first;
  long first_line = 0;
  std::string_view line;
  for (;;) {
    // gzip data holds NUL bytes, which next() rejects as binary: the raw bytes are looked
    // at first, to say what to do about it.
    if (gzip_magic(in.peek(2))) throw Error(path + ": gzip-compressed; decompress it first (gunzip)");
    if (!in.next(line)) throw Error(path + ": empty file; expected a LAMMPS dump or an XYZ file");
    if (!trim(line).empty()) {
      first = std::string(trim(line));
      first_line = in.line_number();
      break;
    }
  }
  in.rewind();
  if (first.rfind("ITEM:", 0) == 0) return std::make_unique<LammpsDumpReader>(std::move(in));
  std::int64_t n;
  std::vector<std::string_view> tok;
  split_ws(first, tok);
  if (tok.size() == 1 && parse_int64(tok[0], n) && n >= 0) return std::make_unique<XyzReader>(std::move(in));
  throw Error(path + ":" + std::to_string(first_line) +
              ": not a particle file: a LAMMPS dump starts with 'ITEM: TIMESTEP', an XYZ file with the particle count; "
              "got " + quote_token(first));
}

void resize_particles(ParticleFrame& f, std::size_t n, double default_radius, bool with_velocity) {
  f.position.resize(n, Vec3::Zero());
  f.radius.resize(n, default_radius);
  f.id.resize(n);
  f.type.resize(n, 1);
  if (with_velocity) {
    f.velocity.resize(n, Vec3::Zero());
    f.velocity_columns = true;
  }
  for (auto& column : f.extra) column.second.resize(n);
}

}  // namespace grainflow::io
