// Writer of extended XYZ particle files that OVITO and ASE (`ase.io.read(path, index=':')`)
// read as they are: Properties=id:I:1:type:I:1:pos:R:3:radius:R:1[:velo:R:3][:omega:R:3]
// + the other extra columns, Lattice/Origin/pbc when the frame has a box, and Time/Timestep.
#pragma once
#include <cstdint>
#include <ostream>
#include <string>

#include "engine/io/particle_file_writer.hpp"

namespace grainflow::io {

// One frame in extended-XYZ text, at the given precision (float64: XyzReader reads the
// frame back exactly).
//  - Types are the integer column `type` (OVITO's Particle Type; an array "type" in ASE),
//    and no species column: ASE takes the species as chemical symbols (a "1" fails with
//    KeyError: '1'), and OVITO maps both `species` and `type` to Particle Type, so the two
//    together would collide. Without species ASE gives every particle the symbol X
//    (atomic number 0). A frame whose types have names (type_names, read from another
//    file) writes them as `species:S:1` instead of `type`.
//  - pos, velo and vectors of extra columns (Bx By Bz, see extra_columns) always have
//    three components, z = 0 in 2D: ASE needs positions (N, 3), and OVITO maps omega:R:3
//    to Angular Velocity X, Y, Z (a 2D disk's spin is its z component).
//  - A 2D frame whose box has no thickness gets a unit z-extent (lo.z − 0.5 … lo.z + 0.5)
//    so that ASE and OVITO see a valid 3 × 3 cell (Lattice) with the disks in its middle
//    plane (Origin, which OVITO reads; ASE keeps it in atoms.info).
//  - Characters that would break the Properties syntax (':', '=', '"', blanks) in extra
//    column names are written as '_'.
void write_xyz_frame(std::ostream& out, const ParticleFrame& frame, Precision precision = Precision::float64);

class XyzWriter final : public ParticleFileWriter {
public:
  explicit XyzWriter(const std::string& path, Precision precision = Precision::float64)
      : ParticleFileWriter(path, precision) {}
  XyzWriter(const std::string& path, std::uint64_t resume_size, int resume_frames,
            Precision precision = Precision::float64)
      : ParticleFileWriter(path, precision, resume_size, resume_frames) {}

private:
  void format(std::string& out, const ParticleFrame& frame, std::int64_t step) const override;
};

}  // namespace grainflow::io
