// The common interface of the particle-file readers (LAMMPS/LIGGGHTS dumps, XYZ) used by
// `grainflow render FILE`: frames are streamed one at a time, so a multi-gigabyte
// multi-frame file is never held in memory.
#pragma once
#include <algorithm>
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

#include "engine/core/particle_frame.hpp"

namespace grainflow::io {

using core::ParticleFrame;  // the in-memory frame the binning grid also consumes

class ParticleReader {
public:
  virtual ~ParticleReader() = default;
  // Reads the next frame into `frame` (overwriting it); false at the end of the file.
  // Malformed input throws grainflow::Error naming file:line and what was expected.
  virtual bool next(ParticleFrame& frame) = 0;
  virtual const std::string& path() const = 0;
  virtual std::string_view format() const = 0;  // "xyz" or "lammps-dump"
};

// Opens `path` with the reader its content calls for: a first non-blank line starting
// with "ITEM:" is a LAMMPS/LIGGGHTS text dump, a first line holding only an integer is
// (extended) XYZ. Anything else (including gzip data) throws grainflow::Error.
std::unique_ptr<ParticleReader> open_particle_file(const std::string& path);

// For the readers: resizes every per-particle vector of `f` to `n` (velocity only when
// `with_velocity`; every extra column), new particles at the origin with `default_radius`,
// type 1, id 0, zero velocity and extra values. A frame is sized for what its file can
// plausibly hold (plausible_particles()) and grows with this as lines are read, so a
// header's count alone never decides how much memory is taken.
void resize_particles(ParticleFrame& f, std::size_t n, double default_radius, bool with_velocity);
// The size to grow a frame of `f.size()` particles to, towards `count`: doubling, so that
// growing costs O(1) per particle.
inline std::size_t grown_size(std::size_t size, std::size_t count) {
  return std::min(count, std::max<std::size_t>(2 * size, 4096));
}

}  // namespace grainflow::io
