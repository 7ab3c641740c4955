#include "engine/io/lammps_dump_reader.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "engine/core/error.hpp"

namespace grainflow::io {
namespace {

constexpr std::string_view kItem = "ITEM:";

bool starts_with_item(std::string_view line) { return trim(line).substr(0, kItem.size()) == kItem; }

// Position sets in order of preference.
struct PositionSet {
  const char* names[3];
  bool scaled;
};
constexpr PositionSet kPositionSets[] = {
    {{"x", "y", "z"}, false}, {{"xu", "yu", "zu"}, false}, {{"xs", "ys", "zs"}, true}, {{"xsu", "ysu", "zsu"}, true}};

}  // namespace

LammpsDumpReader::LammpsDumpReader(std::string path) : in_(std::move(path)) {}
LammpsDumpReader::LammpsDumpReader(LineReader&& in) : in_(std::move(in)) {}

bool LammpsDumpReader::next(ParticleFrame& f) {
  return read_frame_or_truncated(in_, [&] { return read_frame(f); });
}

bool LammpsDumpReader::read_frame(ParticleFrame& f) {
  std::string_view line;
  do {
    if (!in_.next(line)) return false;
  } while (trim(line).empty());

  f.clear();
  std::optional<std::int64_t> natoms;
  long natoms_line = 0;
  bool have_box = false;
  std::array<double, 3> box_lo_bound{}, box_hi_bound{}, tilt{};
  bool triclinic = false;
  const long frame_line = in_.line_number();

  auto value_line = [&](const std::string& item) -> std::string_view {
    if (!in_.next(line)) in_.fail_truncated("file ends after 'ITEM: " + printable(item, 80) + "'; expected its value on the next line");
    if (starts_with_item(line)) in_.fail("expected the value of 'ITEM: " + printable(item, 80) + "', got " + quote_token(trim(line)));
    return line;
  };

  // Header items up to ITEM: ATOMS.
  std::string atoms_header;
  for (;;) {
    const std::string_view t = trim(line);
    if (!starts_with_item(t))
      in_.fail("expected an 'ITEM:' header line (a new frame starts with 'ITEM: TIMESTEP'), got " + quote_token(t));
    const std::string item(trim(t.substr(kItem.size())));
    if (item == "TIMESTEP") {
      split_ws(value_line(item), tokens_);
      if (tokens_.size() != 1 || !parse_int64(tokens_[0], f.timestep))
        in_.fail("expected the timestep (one integer), got " + quote_token(trim(line)));
    } else if (item == "TIME") {
      split_ws(value_line(item), tokens_);
      if (tokens_.size() != 1 || !parse_double(tokens_[0], f.time) || !std::isfinite(f.time))
        in_.fail("expected the time (one finite number), got " + quote_token(trim(line)));
    } else if (item == "UNITS") {
      value_line(item);
    } else if (item == "NUMBER OF ATOMS") {
      split_ws(value_line(item), tokens_);
      std::int64_t n;
      if (tokens_.size() != 1 || !parse_int64(tokens_[0], n) || n < 0)
        in_.fail("expected the number of atoms (one non-negative integer), got " + quote_token(trim(line)));
      check_particle_limit(in_, n);
      natoms = n;
      natoms_line = in_.line_number();
    } else if (item.rfind("BOX BOUNDS", 0) == 0) {
      std::vector<std::string_view> flags;
      split_ws(std::string_view(item).substr(10), flags);
      if (!flags.empty() && flags[0] == "abc")
        in_.fail("general triclinic boxes ('BOX BOUNDS abc origin') are not supported; dump with "
                 "a restricted triclinic or orthogonal box");
      triclinic = flags.size() >= 3 && flags[0] == "xy" && flags[1] == "xz" && flags[2] == "yz";
      if (triclinic) flags.erase(flags.begin(), flags.begin() + 3);
      // Very old LAMMPS versions write no boundary flags: periodicity is then unknown (false).
      if (flags.size() != 3 && !flags.empty())
        in_.fail("expected 'ITEM: BOX BOUNDS [xy xz yz] xx yy zz' with three boundary flags (pp, ff, fs, ...), got " +
                 quote_token(t));
      for (int k = 0; k < static_cast<int>(flags.size()); ++k) f.periodic[k] = flags[k] == "pp";
      for (int k = 0; k < 3; ++k) {
        split_ws(value_line(item), tokens_);
        const std::size_t want = triclinic ? 3 : 2;
        if (tokens_.size() != want)
          in_.fail(std::string("expected ") + (triclinic ? "'lo hi tilt'" : "'lo hi'") + " of the box along " +
                   "xyz"[k] + ", got " + quote_token(trim(line)));
        double* const values[3] = {&box_lo_bound[k], &box_hi_bound[k], &tilt[k]};
        // nan, inf and 1e999 (out of range) would make the box, and every scaled position,
        // meaningless; the LAMMPS names of the line's numbers say which one is bad.
        static constexpr const char* kNames[3][3] = {{"xlo", "xhi", "xy"}, {"ylo", "yhi", "xz"}, {"zlo", "zhi", "yz"}};
        for (std::size_t j = 0; j < want; ++j)
          if (!parse_double(tokens_[j], *values[j]) || !std::isfinite(*values[j]))
            in_.fail("column " + std::to_string(j + 1) + " (" + kNames[k][j] + ") of the box bounds: expected a finite number, got " +
                     quote_token(tokens_[j]));
      }
      have_box = true;
    } else if (item.rfind("ATOMS", 0) == 0) {
      atoms_header = item.substr(5);
      break;
    } else if (item.rfind("NUMBER OF ENTRIES", 0) == 0 || item.rfind("ENTRIES", 0) == 0) {
      in_.fail("this is a 'dump local' file (ITEM: " + printable(item) + "); only per-atom dumps are particle files");
    } else {
      in_.fail("unknown header " + quote_token(t) +
               "; expected ITEM: TIMESTEP, TIME, UNITS, NUMBER OF ATOMS, BOX BOUNDS or ATOMS");
    }
    if (!in_.next(line)) in_.fail_truncated("file ends inside the header of the frame starting on line " + std::to_string(frame_line) + "; expected 'ITEM: ATOMS ...'");
  }
  if (!natoms) in_.fail("'ITEM: ATOMS' without a preceding 'ITEM: NUMBER OF ATOMS' in this frame");

  // Column roles.
  std::vector<std::string> cols;
  {
    std::vector<std::string_view> t;
    split_ws(atoms_header, t);
    for (auto c : t) cols.emplace_back(c);
  }
  if (cols.empty()) in_.fail("'ITEM: ATOMS' lists no columns");
  const int ncol = static_cast<int>(cols.size());
  auto find = [&](std::string_view name) -> int {
    const auto it = std::find(cols.begin(), cols.end(), name);
    return it == cols.end() ? -1 : static_cast<int>(it - cols.begin());
  };
  // LIGGGHTS examples write "id type type x y z ...": a repeated column is read as an
  // extra column "<name>_2" (…_3, …) so that nothing in the file goes unchecked.
  for (int i = 0; i < ncol; ++i) {
    int seen = 1;
    for (int j = 0; j < i; ++j) seen += cols[j] == cols[i] || cols[j].rfind(cols[i] + "_", 0) == 0;
    if (seen > 1) cols[i].append(1, '_').append(std::to_string(seen));  // not "_" + ...: GCC 12 -Wrestrict
  }

  enum Role { kExtra, kId, kType, kElement, kPos, kVel, kRadius, kDiameter };
  std::vector<Role> role(ncol, kExtra);
  std::vector<int> axis(ncol, 0);
  bool scaled = false;
  bool have_pos = false, pos_has_z = false;
  for (const auto& set : kPositionSets) {
    const int ix = find(set.names[0]), iy = find(set.names[1]), iz = find(set.names[2]);
    if (ix < 0 || iy < 0) continue;
    role[ix] = role[iy] = kPos;
    axis[ix] = 0, axis[iy] = 1;
    if (iz >= 0) role[iz] = kPos, axis[iz] = 2, pos_has_z = true;
    scaled = set.scaled;
    have_pos = true;
    break;
  }
  if (!have_pos)
    in_.fail("'ITEM: ATOMS" + printable(atoms_header, 160) +
             "' has no position columns; expected x y [z], xu yu [zu], xs ys [zs] or xsu ysu [zsu]");
  if (scaled && !have_box) in_.fail("scaled coordinates need 'ITEM: BOX BOUNDS' before 'ITEM: ATOMS'");
  if (scaled && !pos_has_z && triclinic) in_.fail("scaled triclinic coordinates need zs");
  const int ivx = find("vx"), ivy = find("vy"), ivz = find("vz");
  const bool have_vel = ivx >= 0 && ivy >= 0;
  if (have_vel) {
    role[ivx] = role[ivy] = kVel, axis[ivx] = 0, axis[ivy] = 1;
    if (ivz >= 0) role[ivz] = kVel, axis[ivz] = 2;
  }
  const int iid = find("id"), itype = find("type"), iel = find("element"), irad = find("radius"), idiam = find("diameter");
  if (iid >= 0) role[iid] = kId;
  if (itype >= 0) role[itype] = kType;
  if (iel >= 0) role[iel] = kElement;
  if (irad >= 0) role[irad] = kRadius;
  else if (idiam >= 0) role[idiam] = kDiameter;

  std::string header_desc;
  for (int i = 0; i < ncol && i < 10; ++i) {
    if (i) header_desc.push_back(' ');
    header_desc.append(printable(cols[i]));  // not " " + ...: GCC 12 -Wrestrict false positive
  }
  if (ncol > 10) header_desc += " ...";

  const std::size_t n = static_cast<std::size_t>(*natoms);
  std::vector<int> extra_slot(ncol, -1);
  for (int c = 0; c < ncol; ++c)
    if (role[c] == kExtra) {
      extra_slot[c] = static_cast<int>(f.extra.size());
      f.extra.emplace_back(cols[c], std::vector<double>());
    }
  resize_particles(f, plausible_particles(in_, *natoms, natoms_line, ncol), kDefaultRadius, have_vel);

  for (std::size_t i = 0; i < n; ++i) {
    if (!in_.next(line))
      in_.fail_truncated("file ends after " + std::to_string(i) + " of the " + std::to_string(n) + " atoms announced on line " +
               std::to_string(natoms_line) + " (truncated last frame?)");
    if (i == f.size()) resize_particles(f, grown_size(i, n), kDefaultRadius, have_vel);
    split_ws(line, tokens_);
    if (static_cast<int>(tokens_.size()) != ncol) {
      if (starts_with_item(line))
        in_.fail("expected atom " + std::to_string(i + 1) + " of " + std::to_string(n) +
                 " (NUMBER OF ATOMS on line " + std::to_string(natoms_line) + "), got " + quote_token(trim(line)));
      in_.fail("expected " + std::to_string(ncol) + " columns (" + header_desc + "), got " + std::to_string(tokens_.size()));
    }
    for (int c = 0; c < ncol; ++c) {
      const auto tok = tokens_[c];
      auto num = [&](bool finite) {
        double v;
        if (!parse_double(tok, v) || (finite && !std::isfinite(v)))
          in_.fail("column " + std::to_string(c + 1) + " (" + printable(cols[c]) + "): expected a " + (finite ? "finite " : "") +
                   "number, got " + quote_token(tok));
        return v;
      };
      auto integer = [&]() {
        std::int64_t v;
        if (!parse_int64(tok, v))
          in_.fail("column " + std::to_string(c + 1) + " (" + printable(cols[c]) + "): expected an integer, got " + quote_token(tok));
        return v;
      };
      switch (role[c]) {
        case kExtra: f.extra[extra_slot[c]].second[i] = num(false); break;
        case kId: f.id[i] = integer(); break;
        case kType: f.type[i] = static_cast<int>(integer()); break;
        case kElement: {
          const auto it = std::find(element_names_.begin(), element_names_.end(), tok);
          const int t = static_cast<int>(it - element_names_.begin()) + 1;
          if (it == element_names_.end()) element_names_.emplace_back(tok);
          if (itype < 0) f.type[i] = t;
          break;
        }
        case kPos: f.position[i][axis[c]] = num(true); break;
        case kVel: f.velocity[i][axis[c]] = num(true); break;
        case kRadius:
        case kDiameter: {
          const double v = num(true);
          if (v < 0) in_.fail("column " + std::to_string(c + 1) + " (" + printable(cols[c]) + "): negative value " + quote_token(tok));
          f.radius[i] = role[c] == kRadius ? v : 0.5 * v;
          break;
        }
      }
    }
    if (iid < 0) f.id[i] = static_cast<std::int64_t>(i) + 1;
  }

  if (have_box) {
    f.has_box = true;
    for (int k = 0; k < 3; ++k) f.box_lo[k] = box_lo_bound[k], f.box_hi[k] = box_hi_bound[k];
    f.triclinic = triclinic;
    if (triclinic) f.tilt = {tilt[0], tilt[1], tilt[2]};
  }
  if (scaled) {
    // LAMMPS Howto_triclinic: the bounds written are the bounding box; recover the cell.
    const double xy = f.tilt[0], xz = f.tilt[1], yz = f.tilt[2];
    const double xlo = box_lo_bound[0] - std::min({0.0, xy, xz, xy + xz});
    const double xhi = box_hi_bound[0] - std::max({0.0, xy, xz, xy + xz});
    const double ylo = box_lo_bound[1] - std::min(0.0, yz), yhi = box_hi_bound[1] - std::max(0.0, yz);
    const double zlo = box_lo_bound[2], zhi = box_hi_bound[2];
    for (auto& p : f.position) {
      const Vec3 s = p;
      p = {xlo + s.x() * (xhi - xlo) + s.y() * xy + s.z() * xz, ylo + s.y() * (yhi - ylo) + s.z() * yz,
           pos_has_z ? zlo + s.z() * (zhi - zlo) : 0.0};
    }
  }
  f.type_names = iel >= 0 && itype < 0 ? element_names_ : std::vector<std::string>{};
  f.dim = (!pos_has_z || (n > 0 && std::all_of(f.position.begin(), f.position.end(),
                                               [](const Vec3& p) { return p.z() == 0.0; })))
              ? 2
              : 3;
  return true;
}

}  // namespace grainflow::io
