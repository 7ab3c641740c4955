// system.initial.kind = "file" for both engines: the one mapping from the columns of a
// particle file (extended XYZ such as a run's particles.xyz, a LAMMPS text dump, or a
// LAMMPS data file of atom_style sphere as read_data takes it) to an
// initial state: positions, velocities, angular velocities, radii, masses and types.
// A column the mapping does not know is an error naming it, unless the scene lists it in
// system.initial.ignore: nothing in the file is dropped in silence.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "engine/core/particle_frame.hpp"
#include "engine/core/vec.hpp"
#include "scenes/src/scene/schema.hpp"

namespace grainflow::scenes {
class Scene;
}

namespace grainflow::scenes::initial_file {

inline constexpr Key<std::string> file{"system.initial.file"};
inline constexpr Key<std::int64_t> frame{"system.initial.frame"};
inline constexpr Key<std::vector<std::string>> ignore{"system.initial.ignore"};

// Declares file, frame and ignore in the engine's [system.initial]; `gives` says what the
// engine takes from the file (appended to the key's documentation).
void declare(TableSpec& init, const std::string& gives);

// The state one frame of system.initial.file gives, per particle in file order. Empty
// vectors: the file has no such column (or it is listed in system.initial.ignore).
struct InitialParticles {
  std::string what;                 // `system.initial.file = "name"`, for messages
  core::ParticleFrame frame;        // the frame read (box, time, ids)
  std::vector<Vec3> position;
  std::vector<Vec3> velocity;
  std::vector<Vec3> omega;          // angular velocity [rad per time unit]
  std::vector<double> radius;
  std::vector<double> mass;
  std::vector<double> density;      // a LAMMPS data file's per-atom density
  std::vector<int> type;            // 1-based, as LAMMPS; all 1 when the file has none
  std::size_t size() const { return position.size(); }
};

// Reads the chosen frame (system.initial.frame: 0 the first, −1 the last) of the file
// named by system.initial.file (relative to the scene file) for a `dim`-dimensional run in
// the box [lo, hi]. Throws grainflow::Error naming the file and key when a column is
// unknown, a 2D run's file has z, z-velocity or in-plane spin components, or the file's
// box differs from the scene's.
InitialParticles read(const Scene& sc, int dim, const Vec3& lo, const Vec3& hi);

// The mapping itself, for one frame already read (`what` names its source in messages,
// `skip` is system.initial.ignore): also how tests read a run's particles.xyz back.
InitialParticles map_columns(core::ParticleFrame frame, std::string what, const std::vector<std::string>& skip,
                             int dim);

// The names of the columns the mapping reads (for documentation and messages).
std::string known_columns();

}  // namespace grainflow::scenes::initial_file
