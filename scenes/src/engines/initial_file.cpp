#include "scenes/src/engines/initial_file.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>

#include <fmt/format.h>

#include "engine/core/error.hpp"
#include "engine/io/particle_reader.hpp"
#include "scenes/src/scene/scene.hpp"

namespace grainflow::scenes::initial_file {

namespace {

// What a column beyond the readers' own (id, type/species, positions, radius/diameter,
// velocities) means: LAMMPS dump names first, then extended-XYZ names (a property
// omega:R:3 reads as omega_x, omega_y, omega_z).
enum class Quantity { omega_x, omega_y, omega_z, mass, type };
struct ColumnName {
  std::string_view name;
  Quantity q;
};
constexpr ColumnName kColumns[] = {
    {"omegax", Quantity::omega_x}, {"omegay", Quantity::omega_y}, {"omegaz", Quantity::omega_z},
    {"omega_x", Quantity::omega_x}, {"omega_y", Quantity::omega_y}, {"omega_z", Quantity::omega_z},
    {"omega", Quantity::omega_z},  // a 2D file's one spin component (about z)
    {"mass", Quantity::mass},
    {"type", Quantity::type},      // an XYZ type:I:1 column beside species
};
// Names of the readers' own quantities that system.initial.ignore may also list.
constexpr std::string_view kRadiusNames[] = {"radius", "diameter"};
constexpr std::string_view kVelocityNames[] = {"velocity", "velo", "vx", "vy", "vz"};
constexpr std::string_view kTypeNames[] = {"type", "species"};

template <std::size_t N>
bool among(std::string_view s, const std::string_view (&names)[N]) {
  return std::find(std::begin(names), std::end(names), s) != std::end(names);
}

core::ParticleFrame read_frame(const std::string& what, const std::string& path, std::int64_t wanted) {
  auto reader = io::open_particle_file(path);
  core::ParticleFrame f, next;
  std::int64_t frames = 0;
  if (!reader->next(f)) throw Error(what + ": " + path + " holds no particle frame");
  ++frames;
  // The last frame: read on while there is one (each frame is bounded by the reader).
  for (; wanted < 0 || frames <= wanted; ++frames) {
    if (!reader->next(next)) break;
    std::swap(f, next);
  }
  if (wanted >= 0 && frames <= wanted)
    throw Error(fmt::format("{}: system.initial.frame = {}, but the file holds {} frame(s); allowed: 0..{} or −1 "
                            "(the last)",
                            what, wanted, frames, frames - 1));
  return f;
}

}  // namespace

std::string known_columns() {
  std::string s = "id, type or species, x y z (pos), radius or diameter, vx vy vz (velo)";
  for (const ColumnName& c : kColumns) s += ", " + std::string(c.name);
  return s;
}

void declare(TableSpec& init, const std::string& gives) {
  init.add_string(file, "",
                  "particle file for kind = \"file\" (a run's particles.xyz, extended XYZ or a LAMMPS text dump), path "
                  "relative to the scene file: " + gives +
                      ". Columns read: " + known_columns() +
                      "; any other column is an error unless listed in system.initial.ignore")
      .path();
  init.add_int(frame, -1, "which frame of system.initial.file: 0 the first, −1 the last (a run's final state)")
      .at_least(-1);
  init.add_string_array(ignore, {}, {},
                        "columns of system.initial.file not to read (e.g. LAMMPS \"fx\", \"tqz\"); also \"radius\", "
                        "\"velocity\", \"type\" to leave those to the scene");
}

InitialParticles map_columns(core::ParticleFrame frame_read, std::string source, const std::vector<std::string>& skip,
                             int dim) {
  InitialParticles out;
  out.what = std::move(source);
  out.frame = std::move(frame_read);
  const std::string& what = out.what;
  const core::ParticleFrame& f = out.frame;
  const std::size_t n = f.size();

  std::vector<bool> skip_used(skip.size(), false);
  const auto skipped = [&](std::string_view col) {
    bool hit = false;
    for (std::size_t k = 0; k < skip.size(); ++k)
      if (skip[k] == col) hit = skip_used[k] = true;
    return hit;
  };
  // The readers report radius 0.5 for every particle when the file has no radius or
  // diameter column: such a frame leaves the radii to the scene.
  const bool file_radius = std::any_of(f.radius.begin(), f.radius.end(), [](double r) { return r != 0.5; });
  bool keep_radius = file_radius, keep_velocity = f.has_velocity(), keep_type = true;
  for (std::size_t k = 0; k < skip.size(); ++k) {
    if (among(skip[k], kRadiusNames) && file_radius) keep_radius = false, skip_used[k] = true;
    if (among(skip[k], kVelocityNames) && f.has_velocity()) keep_velocity = false, skip_used[k] = true;
    if (among(skip[k], kTypeNames)) keep_type = false, skip_used[k] = true;
  }

  out.position = f.position;
  if (keep_radius) out.radius = f.radius;
  if (keep_velocity) out.velocity = f.velocity;
  out.type = keep_type ? f.type : std::vector<int>(n, 1);

  std::vector<std::string> unknown;
  std::optional<std::string> seen[5];
  for (const auto& [col, values] : f.extra) {
    if (skipped(col)) continue;
    const ColumnName* c = nullptr;
    for (const ColumnName& k : kColumns)
      if (k.name == col) c = &k;
    if (!c || (c->q == Quantity::type && !keep_type)) {
      if (!c) unknown.push_back(col);
      continue;
    }
    auto& first = seen[int(c->q)];
    if (first)
      throw Error(what + ": the columns \"" + *first + "\" and \"" + col + "\" give the same quantity; list one in "
                  "system.initial.ignore");
    first = col;
    switch (c->q) {
      case Quantity::omega_x:
      case Quantity::omega_y:
      case Quantity::omega_z: {
        if (out.omega.empty()) out.omega.assign(n, Vec3::Zero());
        const int axis = int(c->q) - int(Quantity::omega_x);
        for (std::size_t i = 0; i < n; ++i) out.omega[i][axis] = values[i];
        break;
      }
      case Quantity::mass:
        out.mass = values;
        for (std::size_t i = 0; i < n; ++i)
          if (!(std::isfinite(values[i]) && values[i] > 0))
            throw Error(fmt::format("{}: particle {} has mass {}; allowed: > 0", what, i + 1, values[i]));
        break;
      case Quantity::type:
        for (std::size_t i = 0; i < n; ++i) {
          if (!(values[i] >= 1 && values[i] <= 1e9 && values[i] == std::floor(values[i])))
            throw Error(fmt::format("{}: particle {} has type {}; allowed: an integer ≥ 1", what, i + 1, values[i]));
          out.type[i] = int(values[i]);
        }
        break;
    }
  }
  if (!unknown.empty()) {
    std::string list;
    for (const auto& u : unknown) list += (list.empty() ? "\"" : ", \"") + u + "\"";
    throw Error(what + ": the file has column(s) " + list + " that an initial state does not take; the columns read "
                "are: " + known_columns() + ". To read the file anyway, list them: system.initial.ignore = [" + list +
                "]");
  }
  for (std::size_t k = 0; k < skip.size(); ++k)
    if (!skip_used[k])
      throw Error(what + ": system.initial.ignore lists \"" + skip[k] + "\", which the file has no column of");

  for (std::size_t i = 0; i < n; ++i) {
    const auto bad = [&](const char* quantity, double v) {
      throw Error(fmt::format("{}: particle {} has {} = {}, but the run is two-dimensional; allowed: 0", what, i + 1,
                              quantity, v));
    };
    if (!out.position[i].allFinite())
      throw Error(fmt::format("{}: particle {} has a position that is not finite", what, i + 1));
    if (dim == 2) {
      if (out.position[i].z() != 0.0) bad("z", out.position[i].z());
      if (!out.velocity.empty() && out.velocity[i].z() != 0.0) bad("vz", out.velocity[i].z());
      if (!out.omega.empty() && out.omega[i].x() != 0.0) bad("omegax", out.omega[i].x());
      if (!out.omega.empty() && out.omega[i].y() != 0.0) bad("omegay", out.omega[i].y());
    }
  }
  return out;
}

InitialParticles read(const Scene& sc, int dim, const Vec3& lo, const Vec3& hi) {
  const std::string name = sc.get(file);
  std::filesystem::path path(name);
  if (path.is_relative() && !sc.source().empty()) path = sc.source().parent_path() / path;
  const std::string what = "system.initial.file = \"" + name + "\"";
  InitialParticles out = map_columns(read_frame(what, path.string(), sc.get(frame)), what, sc.get(ignore), dim);
  const core::ParticleFrame& f = out.frame;
  if (f.has_box) {
    for (int a = 0; a < dim; ++a) {
      const double tol = 1e-9 * (hi[a] - lo[a]);
      if (std::abs(f.box_lo[a] - lo[a]) > tol || std::abs(f.box_hi[a] - hi[a]) > tol)
        throw Error(fmt::format("{}: the file's box is [{}, {}] along {}, the scene's box [{}, {}]; allowed: the "
                                "same box",
                                what, f.box_lo[a], f.box_hi[a], "xyz"[a], lo[a], hi[a]));
    }
  }
  return out;
}

}  // namespace grainflow::scenes::initial_file
