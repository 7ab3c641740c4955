#include "engine/io/xyz_writer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <iterator>

#include "engine/core/error.hpp"

namespace grainflow::io {
namespace {

std::string clean_name(std::string_view name) {
  std::string s(name);
  for (auto& c : s)
    if (c == ':' || c == '=' || c == '"' || c == ' ' || c == '\t') c = '_';
  return s.empty() ? std::string("_") : s;
}

void format_frame(std::string& out, const ParticleFrame& f) {
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
  out += "Properties=species:S:1:pos:R:3:radius:R:1";
  if (f.has_velocity()) out += ":velo:R:3";
  out += ":id:I:1";
  for (const auto& e : f.extra) fmt::format_to(it, ":{}:R:1", clean_name(e.first));
  if (!std::isnan(f.time)) fmt::format_to(it, " Time={}", f.time);
  if (f.timestep >= 0) fmt::format_to(it, " Timestep={}", f.timestep);
  out += '\n';
  for (std::size_t i = 0; i < n; ++i) {
    const int t = f.type[i];
    if (t >= 1 && static_cast<std::size_t>(t) <= f.type_names.size()) out += f.type_names[t - 1];
    else fmt::format_to(it, "{}", t);
    const Vec3& p = f.position[i];
    fmt::format_to(it, " {} {} {} {}", p.x(), p.y(), p.z(), f.radius[i]);
    if (f.has_velocity()) {
      const Vec3& v = f.velocity[i];
      fmt::format_to(it, " {} {} {}", v.x(), v.y(), v.z());
    }
    fmt::format_to(it, " {}", f.id[i]);
    for (const auto& e : f.extra) fmt::format_to(it, " {}", e.second[i]);
    out += '\n';
  }
}

}  // namespace

void write_xyz_frame(std::ostream& out, const ParticleFrame& frame) {
  std::string s;
  format_frame(s, frame);
  out << s;
}

XyzWriter::XyzWriter(const std::string& path) : file_(PartialFile::create(path)) {}

XyzWriter::XyzWriter(const std::string& path, std::uint64_t resume_size, int resume_frames)
    : file_(PartialFile::resume(path, resume_size)), frames_(resume_frames) {}

void XyzWriter::write(const ParticleFrame& frame) {
  if (file_.finished()) throw Error(file_.final_path().string() + ": XYZ write after close()");
  buf_.clear();
  format_frame(buf_, frame);
  file_.write(buf_);
  ++frames_;
}

std::uint64_t XyzWriter::flush() {
  file_.flush();
  return file_.size();
}

void XyzWriter::close() { file_.finish(); }

}  // namespace grainflow::io
