#include "engine/io/xyz_writer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>

namespace grainflow::io {
namespace {

std::string clean_name(std::string_view name) {
  std::string s(name);
  for (auto& c : s)
    if (c == ':' || c == '=' || c == '"' || c == ' ' || c == '\t') c = '_';
  return s.empty() ? std::string("_") : s;
}

void format_frame(std::string& out, const ParticleFrame& f, Precision prec) {
  f.check_consistent("write_xyz");
  auto it = std::back_inserter(out);
  const std::size_t n = f.size();
  fmt::format_to(it, "{}\n", n);
  if (f.has_box) {
    Vec3 lo = f.box_lo, len = f.box_hi - f.box_lo;
    if (f.dim == 2 && len.z() <= 0.0) lo.z() -= 0.5, len.z() = 1.0;
    // Tilted cells: LAMMPS convention a = (lx,0,0), b = (xy,ly,0), c = (xz,yz,lz), with the
    // cell recovered from the bounding box as in LAMMPS Howto_triclinic.
    double xy = 0, xz = 0, yz = 0;
    if (f.triclinic) {
      xy = f.tilt[0], xz = f.tilt[1], yz = f.tilt[2];
      lo.x() = f.box_lo.x() - std::min({0.0, xy, xz, xy + xz});
      len.x() = (f.box_hi.x() - std::max({0.0, xy, xz, xy + xz})) - lo.x();
      lo.y() = f.box_lo.y() - std::min(0.0, yz);
      len.y() = (f.box_hi.y() - std::max(0.0, yz)) - lo.y();
    }
    fmt::format_to(it, "Lattice=\"{} 0 0 {} {} 0 {} {} {}\" Origin=\"{} {} {}\" ", len.x(), xy, len.y(), xz, yz,
                   len.z(), lo.x(), lo.y(), lo.z());
    fmt::format_to(it, "pbc=\"{} {} {}\" ", f.periodic[0] ? 'T' : 'F', f.periodic[1] ? 'T' : 'F',
                   f.periodic[2] ? 'T' : 'F');
  }
  const bool named = !f.type_names.empty();
  out += named ? "Properties=species:S:1:id:I:1" : "Properties=id:I:1:type:I:1";
  out += ":pos:R:3:radius:R:1";
  if (f.has_velocity()) out += ":velo:R:3";
  const std::vector<ExtraColumn> extra = extra_columns(f);
  for (const auto& e : extra) fmt::format_to(it, ":{}:R:{}", clean_name(e.name), e.components);
  if (!std::isnan(f.time)) fmt::format_to(it, " Time={}", f.time);
  if (f.timestep >= 0) fmt::format_to(it, " Timestep={}", f.timestep);
  out += '\n';
  auto real = [&](double v) {
    out += ' ';
    append_real(out, v, prec);
  };
  for (std::size_t i = 0; i < n; ++i) {
    const int t = f.type[i];
    if (named) {
      if (t >= 1 && static_cast<std::size_t>(t) <= f.type_names.size()) out += f.type_names[t - 1];
      else fmt::format_to(it, "{}", t);
      fmt::format_to(it, " {}", f.id[i]);
    } else {
      fmt::format_to(it, "{} {}", f.id[i], t);
    }
    const Vec3& p = f.position[i];
    real(p.x()), real(p.y()), real(p.z()), real(f.radius[i]);
    if (f.has_velocity()) {
      const Vec3& v = f.velocity[i];
      real(v.x()), real(v.y()), real(v.z());
    }
    for (const auto& e : extra)
      for (int k = 0; k < e.components; ++k) real((*e.values[k])[i]);
    out += '\n';
  }
}

}  // namespace

void write_xyz_frame(std::ostream& out, const ParticleFrame& frame, Precision precision) {
  std::string s;
  format_frame(s, frame, precision);
  out << s;
}

void XyzWriter::format(std::string& out, const ParticleFrame& frame, std::int64_t) const {
  format_frame(out, frame, precision());
}

}  // namespace grainflow::io
