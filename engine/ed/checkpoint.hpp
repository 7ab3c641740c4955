// Small helpers for the ED engine's checkpoints (Simulation::save_state / load_state and the
// agents' save/load): Eigen vectors field by field (flags and random streams: the
// archive's own flag() and rng()).
#pragma once
#include <cstdint>
#include <string>

#include "engine/core/vec.hpp"
#include "engine/io/archive.hpp"

namespace grainflow::ed::checkpoint {

inline void write_vec2(io::ArchiveWriter& w, const Vec2& v) {
  w.pod(v.x());
  w.pod(v.y());
}
inline Vec2 read_vec2(io::ArchiveReader& r) {
  const double x = r.get<double>();
  const double y = r.get<double>();
  return {x, y};
}

}  // namespace grainflow::ed::checkpoint
