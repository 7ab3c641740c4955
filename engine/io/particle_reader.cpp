#include "engine/io/particle_reader.hpp"

#include "engine/core/error.hpp"
#include "engine/io/lammps_dump_reader.hpp"
#include "engine/io/line_reader.hpp"
#include "engine/io/xyz_reader.hpp"

namespace grainflow::io {

std::unique_ptr<ParticleReader> open_particle_file(const std::string& path) {
  std::string first;
  long first_line = 0;
  {
    LineReader probe(path);
    std::string_view line;
    while (probe.next(line)) {
      if (line.size() >= 2 && static_cast<unsigned char>(line[0]) == 0x1f && static_cast<unsigned char>(line[1]) == 0x8b)
        throw Error(path + ": gzip-compressed; decompress it first (gunzip)");
      if (!trim(line).empty()) {
        first = std::string(trim(line));
        first_line = probe.line_number();
        break;
      }
    }
    if (first.empty()) throw Error(path + ": empty file; expected a LAMMPS dump or an XYZ file");
  }
  if (first.rfind("ITEM:", 0) == 0) return std::make_unique<LammpsDumpReader>(path);
  std::int64_t n;
  std::vector<std::string_view> tok;
  split_ws(first, tok);
  if (tok.size() == 1 && parse_int64(tok[0], n) && n >= 0) return std::make_unique<XyzReader>(path);
  throw Error(path + ":" + std::to_string(first_line) +
              ": not a particle file: a LAMMPS dump starts with 'ITEM: TIMESTEP', an XYZ file with the particle count; "
              "got " + quote_token(first));
}

}  // namespace grainflow::io
