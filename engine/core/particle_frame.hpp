// One particle snapshot as read from (or written to) a particle file: LAMMPS/LIGGGHTS
// dumps, extended XYZ. The renderer colours particles by any column through column();
// the binning code (seed 003 §4.1) turns a frame into fields.
#pragma once
#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "engine/core/vec.hpp"

namespace grainflow::core {

struct ParticleFrame {
  // 2 when the file is two-dimensional: every z is exactly 0 (LAMMPS 2D runs, 2D XYZ) or
  // positions have two components; 3 otherwise.
  int dim = 3;
  double time = std::numeric_limits<double>::quiet_NaN();  // NaN if the file does not say
  std::int64_t timestep = -1;                                // -1 if the file does not say

  bool has_box = false;
  Vec3 box_lo{0.0, 0.0, 0.0};
  Vec3 box_hi{0.0, 0.0, 0.0};
  // A tilted (triclinic) cell: box_lo/box_hi are then its axis-aligned bounding box, and
  // `tilt` = (xy, xz, yz) as LAMMPS defines them.
  bool triclinic = false;
  Vec3 tilt{0.0, 0.0, 0.0};
  std::array<bool, 3> periodic{false, false, false};

  // Per particle, all of length size() (velocity may be empty).
  std::vector<std::int64_t> id;
  std::vector<Vec3> position;
  std::vector<double> radius;
  std::vector<Vec3> velocity;  // empty when the file has none
  // The file has velocity columns, even in a frame of 0 particles (a LAMMPS `fix pour`
  // dump starts empty): has_velocity() and the columns vx, vy, vz, speed then exist.
  bool velocity_columns = false;
  std::vector<int> type;       // 1-based, as LAMMPS
  // Optional names of types: type_names[t - 1] is the species name of type t (XYZ element
  // symbols, LAMMPS `element`). Empty when types are plain numbers.
  std::vector<std::string> type_names;
  // Every other numeric per-particle column, in file order (name -> values).
  std::vector<std::pair<std::string, std::vector<double>>> extra;

  std::size_t size() const { return position.size(); }
  bool has_velocity() const { return velocity_columns || !velocity.empty(); }

  // Values of a named per-particle column, or nullptr when there is none. Serves, before
  // the extra columns: "id", "type", "x", "y", "z", "radius", "diameter", and with
  // velocities "vx", "vy", "vz", "speed" (|v|). Derived columns are computed on first use
  // and cached: call invalidate_columns() after changing the per-particle vectors. The
  // returned pointer stays valid until then (the cache never moves its vectors); the
  // cache makes concurrent calls on one frame unsafe.
  const std::vector<double>* column(std::string_view name) const;
  // Every name column() answers for this frame.
  std::vector<std::string> column_names() const;
  void invalidate_columns() { cache_.clear(); }

  // Empties the frame (keeps capacity), resets time/step/box to "unknown".
  void clear();
  // Throws grainflow::Error (naming `where`) when vectors have inconsistent lengths.
  void check_consistent(std::string_view where) const;

private:
  mutable std::map<std::string, std::vector<double>, std::less<>> cache_;
};

}  // namespace grainflow::core
