// Writer of LAMMPS text dumps (the `dump custom` layout) that LAMMPS `read_dump`/`rerun`,
// OVITO and `grainflow render` read:
//   ITEM: TIME / ITEM: TIMESTEP / ITEM: NUMBER OF ATOMS / ITEM: BOX BOUNDS [xy xz yz] bx by bz
//   ITEM: ATOMS id type radius x y z [vx vy vz] [omegax omegay omegaz] [other columns]
#pragma once
#include <cstdint>
#include <ostream>
#include <string>

#include "engine/io/particle_file_writer.hpp"

namespace grainflow::io {

// One frame as LAMMPS writes it with `dump_modify time yes`:
//  - ITEM: TIME (the frame's time, when known) comes before ITEM: TIMESTEP, as in LAMMPS.
//  - TIMESTEP is the frame's own step (frame.timestep, the DEM engine's step count) or, when
//    it has none (the ED engine makes events, not steps), `step`: the caller's frame number.
//  - Boundary flags per axis: pp periodic, ff otherwise (walls, open stream ends). A 2D frame
//    is written as LAMMPS writes a 2D run: z = 0, z bounds lo.z − 0.5 … lo.z + 0.5 when the
//    box has no thickness, and z periodic (LAMMPS requires a periodic z in 2D).
//  - A frame without a box gets its particles' bounding box (ff).
//  - omegax omegay omegaz are the frame's extra vector omega (extra_columns); every other
//    extra column follows under its own name (blanks written as '_'), a vector B as Bx By Bz.
void write_lammps_dump_frame(std::ostream& out, const ParticleFrame& frame, std::int64_t step,
                             Precision precision = Precision::float64);

class LammpsDumpWriter final : public ParticleFileWriter {
public:
  explicit LammpsDumpWriter(const std::string& path, Precision precision = Precision::float64)
      : ParticleFileWriter(path, precision) {}
  LammpsDumpWriter(const std::string& path, std::uint64_t resume_size, int resume_frames,
                   Precision precision = Precision::float64)
      : ParticleFileWriter(path, precision, resume_size, resume_frames) {}

private:
  void format(std::string& out, const ParticleFrame& frame, std::int64_t step) const override;
};

}  // namespace grainflow::io
