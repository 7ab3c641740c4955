// Reader for XYZ particle files: extended XYZ as written by ASE and OVITO (line 2 holds
// key=value pairs: Lattice, Origin, Properties, Time, Timestep, pbc) and plain XYZ
// (species x y z [more columns]), single- or multi-frame, streamed frame by frame.
//
// Column mapping (extended XYZ, names case-insensitive): species|element -> type (and
// type_names); pos -> position (2 or 3 components; 2 means a 2D frame); radius|radii ->
// radius; diameter -> radius = diameter / 2; velo|vel|velocity|velocities -> velocity;
// id -> id; an integer `type` column -> type when there is no species column. Every other
// R/I/L property becomes an extra column (L as 0/1; a k-component property `f` becomes
// f_x, f_y, f_z for k = 3, else f_0 ... f_{k-1}); other string properties are not read.
// Plain XYZ: columns 5, 6, ... become extra columns "column5", "column6", ...
// A file that ends inside a frame throws io::TruncatedFrame (line_reader.hpp).
// Without a radius or diameter column every radius is 0.5 (unit diameter, the ED unit σ).
// Species: if the first species of the file is an integer, species are type numbers
// (LAMMPS `dump xyz`); otherwise every species is a name, typed 1, 2, ... in order of
// first appearance, which stays fixed for the whole file.
#pragma once
#include <string>
#include <vector>

#include "engine/io/line_reader.hpp"
#include "engine/io/particle_reader.hpp"

namespace grainflow::io {

class XyzReader final : public ParticleReader {
public:
  explicit XyzReader(std::string path);
  // Reads from an already open file (open_particle_file() hands over its probe).
  explicit XyzReader(LineReader&& in);
  bool next(ParticleFrame& frame) override;
  const std::string& path() const override { return in_.path(); }
  std::string_view format() const override { return "xyz"; }

  static constexpr double kDefaultRadius = 0.5;

private:
  bool read_frame(ParticleFrame& frame);
  int species_type(std::string_view species);

  LineReader in_;
  enum class SpeciesMode { unknown, numeric, named } mode_ = SpeciesMode::unknown;
  std::vector<std::string> names_;
  std::vector<std::string_view> tokens_;
};

}  // namespace grainflow::io
