// Reader for LAMMPS / LIGGGHTS text dumps (`dump custom`, `dump atom`): any number of
// frames, streamed one at a time (ITEM: TIMESTEP / TIME / UNITS / NUMBER OF ATOMS /
// BOX BOUNDS / ATOMS).
//
// Positions: x y z, else unwrapped xu yu zu, else scaled xs ys zs (then xsu ysu zsu),
// converted with the box (triclinic too); the other position sets become extra columns.
// z may be absent (2D). radius (LIGGGHTS) or diameter (radius = diameter / 2); without
// either every radius is 0.5. vx vy [vz] -> velocity. id, type; a string `element` column
// names the types. Every other column (mass, ix, c_..., f_..., v_...) is an extra column.
// A triclinic box (BOX BOUNDS xy xz yz ...) is kept as its bounding box plus the tilts.
// A frame of 0 atoms keeps its columns' meaning (has_velocity(): `fix pour` dumps start
// empty). A file that ends inside a frame throws io::TruncatedFrame (line_reader.hpp).
#pragma once
#include <string>
#include <vector>

#include "engine/io/line_reader.hpp"
#include "engine/io/particle_reader.hpp"

namespace grainflow::io {

class LammpsDumpReader final : public ParticleReader {
public:
  explicit LammpsDumpReader(std::string path);
  // Reads from an already open file (open_particle_file() hands over its probe).
  explicit LammpsDumpReader(LineReader&& in);
  bool next(ParticleFrame& frame) override;
  const std::string& path() const override { return in_.path(); }
  std::string_view format() const override { return "lammps-dump"; }

  static constexpr double kDefaultRadius = 0.5;

private:
  bool read_frame(ParticleFrame& frame);

  LineReader in_;
  std::vector<std::string_view> tokens_;
  std::vector<std::string> element_names_;
};

}  // namespace grainflow::io
