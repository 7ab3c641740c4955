// What the particle-file writers (extended XYZ, LAMMPS text dumps) share: the precision of
// their real numbers, and a multi-frame file that grows through PartialFile so that a
// killed run leaves a usable `.partial` and a resumed one continues it.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "engine/core/particle_frame.hpp"
#include "engine/io/partial_file.hpp"

namespace grainflow::io {

using core::ParticleFrame;  // the in-memory frame the binning grid also consumes

// float64: every real in the shortest text that reads back to the same double (a file
// read back gives the frame bit for bit: for checks and restarts). float32: the value
// rounded to the nearest float and written in the shortest text that reads back to that
// float (≈ 7 significant digits instead of ≈ 16: a run's files shrink to about two
// thirds, as zeros and small integers stay short either way). Integers (ids, types) and the
// header (box, time) are exact either way.
enum class Precision { float64, float32 };

// Appends v as text at the given precision.
void append_real(std::string& out, double v, Precision p);

// A frame's extra columns as the writers see them: three consecutive columns named
// Bx, By, Bz or B_x, B_y, B_z (omegax omegay omegaz, as LAMMPS names them, or what
// XyzReader makes of an omega:R:3 property) are one vector named B; every other column is
// a scalar under its own name.
struct ExtraColumn {
  std::string name;
  int components = 1;                                    // 1 or 3
  const std::vector<double>* values[3] = {nullptr, nullptr, nullptr};
};
std::vector<ExtraColumn> extra_columns(const ParticleFrame& frame);

// Multi-frame file: frames go to PATH.partial, which close() renames to PATH, so a killed
// run never leaves a truncated file under the final name; a writer destroyed without
// close() (a killed or failed run) leaves the .partial with the frames written so far, and
// a resumed run continues it from its checkpoint's size.
class ParticleFileWriter {
public:
  ParticleFileWriter(const ParticleFileWriter&) = delete;
  ParticleFileWriter& operator=(const ParticleFileWriter&) = delete;
  virtual ~ParticleFileWriter() = default;

  // `step` is the frame's number in the run, for formats that need a step when the frame
  // has none (a LAMMPS dump's TIMESTEP); others ignore it.
  void write(const ParticleFrame& frame, std::int64_t step = 0);
  // Flushes; the bytes written so far (what a checkpoint records).
  std::uint64_t flush();
  void close();  // flushes and renames into place; throws grainflow::Error on I/O failure
  int frames() const { return frames_; }
  Precision precision() const { return precision_; }

protected:
  ParticleFileWriter(const std::string& path, Precision precision);
  ParticleFileWriter(const std::string& path, Precision precision, std::uint64_t resume_size, int resume_frames);
  virtual void format(std::string& out, const ParticleFrame& frame, std::int64_t step) const = 0;

private:
  PartialFile file_;
  Precision precision_;
  int frames_ = 0;
  std::string buf_;
};

}  // namespace grainflow::io
