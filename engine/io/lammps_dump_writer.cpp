#include "engine/io/lammps_dump_writer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <limits>

namespace grainflow::io {
namespace {

std::string column_name(std::string_view name) {
  std::string s(name);
  for (auto& c : s)
    if (c == ' ' || c == '\t' || c == '\n' || c == '\r') c = '_';
  return s.empty() ? std::string("_") : s;
}

void format_frame(std::string& out, const ParticleFrame& f, std::int64_t step, Precision prec) {
  f.check_consistent("write_lammps_dump");
  auto it = std::back_inserter(out);
  const std::size_t n = f.size();
  if (!std::isnan(f.time)) fmt::format_to(it, "ITEM: TIME\n{}\n", f.time);
  fmt::format_to(it, "ITEM: TIMESTEP\n{}\nITEM: NUMBER OF ATOMS\n{}\n", f.timestep >= 0 ? f.timestep : step, n);

  Vec3 lo = f.box_lo, hi = f.box_hi;
  std::array<bool, 3> periodic = f.periodic;
  if (!f.has_box) {
    lo = Vec3::Constant(n ? std::numeric_limits<double>::max() : 0.0);
    hi = Vec3::Constant(n ? std::numeric_limits<double>::lowest() : 0.0);
    for (const Vec3& p : f.position) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    periodic = {false, false, false};
  }
  if (f.dim == 2) {
    if (hi.z() <= lo.z()) lo.z() -= 0.5, hi.z() = lo.z() + 1.0;
    periodic[2] = true;
  }
  auto flag = [&](int k) { return periodic[k] ? "pp" : "ff"; };
  fmt::format_to(it, "ITEM: BOX BOUNDS {}{} {} {}\n", f.triclinic ? "xy xz yz " : "", flag(0), flag(1), flag(2));
  for (int k = 0; k < 3; ++k) {
    if (f.triclinic) fmt::format_to(it, "{} {} {}\n", lo[k], hi[k], f.tilt[k]);
    else fmt::format_to(it, "{} {}\n", lo[k], hi[k]);
  }

  const std::vector<ExtraColumn> extra = extra_columns(f);
  const ExtraColumn* omega = nullptr;
  for (const auto& e : extra)
    if (e.name == "omega" && e.components == 3) omega = &e;
  out += "ITEM: ATOMS id type radius x y z";
  if (f.has_velocity()) out += " vx vy vz";
  if (omega) out += " omegax omegay omegaz";
  for (const auto& e : extra) {
    if (&e == omega) continue;
    const std::string name = column_name(e.name);
    if (e.components == 1) fmt::format_to(it, " {}", name);
    else fmt::format_to(it, " {0}x {0}y {0}z", name);
  }
  out += '\n';
  auto real = [&](double v) {
    out += ' ';
    append_real(out, v, prec);
  };
  for (std::size_t i = 0; i < n; ++i) {
    fmt::format_to(it, "{} {}", f.id[i], f.type[i]);
    real(f.radius[i]);
    const Vec3& p = f.position[i];
    real(p.x()), real(p.y()), real(p.z());
    if (f.has_velocity()) {
      const Vec3& v = f.velocity[i];
      real(v.x()), real(v.y()), real(v.z());
    }
    if (omega)
      for (int k = 0; k < 3; ++k) real((*omega->values[k])[i]);
    for (const auto& e : extra) {
      if (&e == omega) continue;
      for (int k = 0; k < e.components; ++k) real((*e.values[k])[i]);
    }
    out += '\n';
  }
}

}  // namespace

void write_lammps_dump_frame(std::ostream& out, const ParticleFrame& frame, std::int64_t step, Precision precision) {
  std::string s;
  format_frame(s, frame, step, precision);
  out << s;
}

void LammpsDumpWriter::format(std::string& out, const ParticleFrame& frame, std::int64_t step) const {
  format_frame(out, frame, step, precision());
}

}  // namespace grainflow::io
