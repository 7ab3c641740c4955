#include "scenes/src/engines/initial_file.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>

#include <fmt/format.h>

#include "engine/core/error.hpp"
#include "engine/io/line_reader.hpp"
#include "engine/io/particle_reader.hpp"
#include "scenes/src/scene/scene.hpp"

namespace grainflow::scenes::initial_file {

namespace {

// What a column beyond the readers' own (id, type/species, positions, radius/diameter,
// velocities) means: LAMMPS dump names first, then extended-XYZ names (a property
// omega:R:3 reads as omega_x, omega_y, omega_z).
enum class Quantity { omega_x, omega_y, omega_z, mass, type, density };
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
    {"density", Quantity::density},  // a LAMMPS data file's per-atom density
};
// Names of the readers' own quantities that system.initial.ignore may also list.
constexpr std::string_view kRadiusNames[] = {"radius", "diameter"};
constexpr std::string_view kVelocityNames[] = {"velocity", "velo", "vx", "vy", "vz"};
constexpr std::string_view kTypeNames[] = {"type", "species"};

template <std::size_t N>
bool among(std::string_view s, const std::string_view (&names)[N]) {
  return std::find(std::begin(names), std::end(names), s) != std::end(names);
}

// A LAMMPS data file (read_data / write_data): a title line, then a header with
// "N atoms". Dumps start with "ITEM:" and XYZ files with a count alone, so neither matches.
bool is_lammps_data(const std::string& path) {
  io::LineReader in(path);
  std::string_view line;
  std::vector<std::string_view> t;
  if (!in.next(line)) return false;
  if (io::trim(line).rfind("ITEM:", 0) == 0) return false;
  for (int k = 0; k < 64 && in.next(line); ++k) {
    io::split_ws(line.substr(0, line.find('#')), t);
    std::int64_t n;
    if (t.size() == 2 && t[1] == "atoms" && io::parse_int64(t[0], n)) return true;
    if (t.size() == 1 && !io::parse_int64(t[0], n)) return false;  // a lone XYZ count parses; a word does not
  }
  return false;
}

// The state of a LAMMPS data file of atom_style sphere as a frame: header "N atoms",
// "xlo xhi" …; "Atoms # sphere": id type diameter density x y z [ix iy iz] (image flags do
// not move an in-box position); "Velocities": id vx vy vz omegax omegay omegaz. Density
// comes as the column "density". Other sections (Masses, Pair Coeffs, …) are refused:
// what they say is the scene's to say.
core::ParticleFrame read_lammps_data(const std::string& path) {
  io::LineReader in(path);
  std::string_view line;
  std::vector<std::string_view> t;
  core::ParticleFrame f;
  std::int64_t natoms = -1;
  in.next(line);  // the title
  const auto num = [&](std::string_view tok) {
    double v;
    if (!io::parse_double(tok, v) || !std::isfinite(v)) in.fail("expected a number, got " + io::quote_token(tok));
    return v;
  };
  const auto id_of = [&](std::string_view tok) {
    std::int64_t v;
    if (!io::parse_int64(tok, v) || v < 1) in.fail("expected an atom id ≥ 1, got " + io::quote_token(tok));
    return v;
  };
  std::string section;
  std::vector<double> density, wx, wy, wz;
  std::vector<std::int64_t> vel_id;
  std::vector<Vec3> vel;
  while (in.next(line)) {
    const std::string_view body = io::trim(line.substr(0, line.find('#')));
    if (body.empty()) continue;
    io::split_ws(body, t);
    if (section.empty() && !std::isdigit(static_cast<unsigned char>(body[0])) && body[0] != '-' && body[0] != '+' &&
        body[0] != '.') {
      section = std::string(body);
      if (section != "Atoms" && section != "Velocities")
        in.fail("section \"" + io::printable(section) + "\" is not read for an initial state (only Atoms and "
                "Velocities of atom_style sphere); give such settings in the scene");
      if (natoms < 0) in.fail("the header has no \"N atoms\" line before the " + section + " section");
      const std::string_view comment = line.find('#') == std::string_view::npos ? "" : io::trim(line.substr(line.find('#') + 1));
      if (section == "Atoms" && !comment.empty() && comment != "sphere")
        in.fail("Atoms # " + io::printable(comment) + ": only atom_style sphere is read");
      // The section's lines follow.
      const std::size_t n = std::size_t(natoms);
      for (std::size_t i = 0; i < n;) {
        if (!in.next(line)) in.fail("the " + section + " section ends after " + std::to_string(i) + " of " +
                                    std::to_string(n) + " lines");
        const std::string_view b = io::trim(line.substr(0, line.find('#')));
        if (b.empty()) continue;
        io::split_ws(b, t);
        if (section == "Atoms") {
          if (t.size() != 7 && t.size() != 10)
            in.fail("expected 7 or 10 columns (id type diameter density x y z [ix iy iz], atom_style sphere), got " +
                    std::to_string(t.size()));
          f.id.push_back(id_of(t[0]));
          const double type = num(t[1]);
          if (type < 1 || type != std::floor(type)) in.fail("expected an atom type ≥ 1, got " + io::quote_token(t[1]));
          f.type.push_back(int(type));
          f.radius.push_back(0.5 * num(t[2]));
          density.push_back(num(t[3]));
          f.position.emplace_back(num(t[4]), num(t[5]), num(t[6]));
        } else {
          if (t.size() != 7)
            in.fail("expected 7 columns (id vx vy vz omegax omegay omegaz, atom_style sphere), got " +
                    std::to_string(t.size()));
          vel_id.push_back(id_of(t[0]));
          vel.emplace_back(num(t[1]), num(t[2]), num(t[3]));
          wx.push_back(num(t[4]));
          wy.push_back(num(t[5]));
          wz.push_back(num(t[6]));
        }
        ++i;
      }
      section.clear();
      continue;
    }
    std::int64_t n;
    if (t.size() == 2 && t[1] == "atoms" && io::parse_int64(t[0], n)) {
      io::check_particle_limit(in, n);
      natoms = n;
    } else if (t.size() == 4 && t[3].size() == 2 + 1 && t[3].substr(1) == "hi" && t[2].size() == 3 &&
               t[2].substr(1) == "lo") {
      const int a = t[2][0] == 'x' ? 0 : t[2][0] == 'y' ? 1 : t[2][0] == 'z' ? 2 : -1;
      if (a < 0) in.fail("unexpected header line " + io::quote_token(body));
      f.box_lo[a] = num(t[0]);
      f.box_hi[a] = num(t[1]);
      f.has_box = true;
    } else if (t.size() == 3 && t[1] == "atom" && t[2] == "types") {
      // the number of atom types: the scene's groups say what they are
    } else if (t.size() >= 2 && (t.back() == "types" || t.back() == "bonds" || t.back() == "angles" ||
                                 t.back() == "dihedrals" || t.back() == "impropers")) {
      if (!(io::parse_int64(t[0], n) && n == 0))
        in.fail("\"" + io::printable(body) + "\": molecular topology is not read for an initial state");
    } else if (t.size() == 4 && t[3] == "yz") {
      in.fail("a tilted (triclinic) box is not read for an initial state");
    } else {
      in.fail("unexpected header line " + io::quote_token(body));
    }
  }
  if (natoms < 0 || f.position.size() != std::size_t(natoms))
    throw Error(path + ": a LAMMPS data file needs an \"N atoms\" header and its Atoms section");
  f.dim = 3;
  f.timestep = 0;
  if (!vel.empty()) {
    // Velocities are keyed by atom id, in any order.
    std::vector<std::size_t> row_of_id;
    for (std::size_t i = 0; i < f.size(); ++i) {
      const auto id = std::size_t(f.id[i]);
      if (id >= row_of_id.size()) row_of_id.resize(id + 1, SIZE_MAX);
      row_of_id[id] = i;
    }
    f.velocity.assign(f.size(), Vec3::Zero());
    std::vector<double> ox(f.size()), oy(f.size()), oz(f.size());
    for (std::size_t k = 0; k < vel.size(); ++k) {
      const auto id = std::size_t(vel_id[k]);
      if (id >= row_of_id.size() || row_of_id[id] == SIZE_MAX)
        throw Error(path + ": Velocities names atom " + std::to_string(id) + ", which the Atoms section lacks");
      const std::size_t i = row_of_id[id];
      f.velocity[i] = vel[k];
      ox[i] = wx[k], oy[i] = wy[k], oz[i] = wz[k];
    }
    f.extra.emplace_back("omegax", std::move(ox));
    f.extra.emplace_back("omegay", std::move(oy));
    f.extra.emplace_back("omegaz", std::move(oz));
  }
  f.extra.emplace_back("density", std::move(density));
  return f;
}

core::ParticleFrame read_frame(const std::string& what, const std::string& path, std::int64_t wanted) {
  if (std::filesystem::is_regular_file(path) && is_lammps_data(path)) {
    if (wanted > 0)
      throw Error(fmt::format("{}: system.initial.frame = {}, but a LAMMPS data file holds one state; allowed: 0 or −1",
                              what, wanted));
    return read_lammps_data(path);
  }
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
  std::optional<std::string> seen[6];
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
      case Quantity::density:
        out.density = values;
        for (std::size_t i = 0; i < n; ++i)
          if (!(std::isfinite(values[i]) && values[i] > 0))
            throw Error(fmt::format("{}: particle {} has density {}; allowed: > 0", what, i + 1, values[i]));
        break;
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
