// Writer of extended XYZ particle files that OVITO, ParaView and ASE open, carrying the
// particle radius (Properties=species:S:1:pos:R:3:radius:R:1:velo:R:3:id:I:1 + extra
// columns), Lattice/Origin/pbc when the frame has a box, and Time/Timestep.
#pragma once
#include <cstdio>
#include <ostream>
#include <string>

#include "engine/io/partial_file.hpp"
#include "engine/core/particle_frame.hpp"

namespace grainflow::io {

using core::ParticleFrame;  // the in-memory frame the binning grid also consumes

// One frame in extended-XYZ text. Numbers are written in the shortest form that reads
// back to the same double, so XyzReader round-trips a frame exactly. Species are
// type_names[type - 1] when present, else the type number. A 2D frame whose box has no
// thickness gets a unit z-extent (lo.z − 0.5 … lo.z + 0.5) so viewers see a valid cell.
// Characters that would break the Properties syntax (':', '=', '"', blanks) in extra
// column names are written as '_'.
void write_xyz_frame(std::ostream& out, const ParticleFrame& frame);

// Multi-frame file writer through PartialFile: frames go to PATH.partial, which close()
// renames to PATH, so a killed run never leaves a truncated file under the final name; a
// writer destroyed without close() (a killed or failed run) leaves the .partial with the
// frames written so far, and a resumed run continues it from its checkpoint's size.
class XyzWriter {
public:
  explicit XyzWriter(const std::string& path);
  XyzWriter(const std::string& path, std::uint64_t resume_size, int resume_frames);
  ~XyzWriter() = default;
  // Flushes; the bytes written so far (what a checkpoint records).
  std::uint64_t flush();
  XyzWriter(const XyzWriter&) = delete;
  XyzWriter& operator=(const XyzWriter&) = delete;

  void write(const ParticleFrame& frame);
  void close();  // flushes and renames into place; throws grainflow::Error on I/O failure
  int frames() const { return frames_; }

private:
  PartialFile file_;
  int frames_ = 0;
  std::string buf_;
};

}  // namespace grainflow::io
