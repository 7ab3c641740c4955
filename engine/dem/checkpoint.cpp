// Binary checkpoint of a DEM run (seed 000 §2.2 DUMPREAD/DATASAVE): configuration, the
// full particle state at the half step, the Verlet table with every contact's history and
// the wall contacts' history, so that a restored run continues bit for bit.
#include <cstring>
#include <fstream>
#include <type_traits>

#include "engine/io/atomic_file.hpp"
#include "engine/core/error.hpp"
#include "engine/dem/simulation.hpp"

namespace grainflow::dem {

namespace {

constexpr char kMagic[8] = {'G', 'F', 'D', 'E', 'M', 'C', 'K', '1'};

struct Writer {
  std::ofstream& os;
  template <class T>
  void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    os.write(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  template <class T>
  void vec(const std::vector<T>& v) {
    pod(static_cast<std::uint64_t>(v.size()));
    if (!v.empty()) os.write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(T)));
  }
};

struct Reader {
  std::ifstream& is;
  std::string file;
  void check() {
    if (!is) throw Error("dem: checkpoint " + file + " is truncated or unreadable");
  }
  template <class T>
  void pod(T& v) {
    is.read(reinterpret_cast<char*>(&v), sizeof(T));
    check();
  }
  template <class T>
  void vec(std::vector<T>& v) {
    std::uint64_t n = 0;
    pod(n);
    if (n > (std::uint64_t(1) << 36)) throw Error("dem: checkpoint " + file + " is corrupt (array of " + std::to_string(n) + " entries)");
    v.resize(n);
    if (n) is.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(n * sizeof(T)));
    check();
  }
};

void write_vec3(Writer& w, const Vec3& v) {
  for (int a = 0; a < 3; ++a) w.pod(v[a]);
}
void read_vec3(Reader& r, Vec3& v) {
  for (int a = 0; a < 3; ++a) r.pod(v[a]);
}

}  // namespace

void Simulation::save_checkpoint(const std::filesystem::path& file) const {
  io::AtomicFile af(file);
  {
    std::ofstream os(af.path(), std::ios::binary | std::ios::trunc);
    Writer w{os};
    os.write(kMagic, sizeof kMagic);
    // configuration
    write_vec3(w, cfg_.box.lo);
    write_vec3(w, cfg_.box.hi);
    for (bool b : cfg_.box.periodic) w.pod(b);
    w.pod(cfg_.box.open_top);
    for (const Vec3& u : cfg_.box.wall_velocity) write_vec3(w, u);
    w.pod(static_cast<std::uint32_t>(cfg_.groups.size()));
    for (const GroupConfig& g : cfg_.groups) {
      w.pod(g.radius);
      w.pod(g.density);
      w.pod(g.contact);
    }
    w.pod(cfg_.mixed_contact.has_value());
    if (cfg_.mixed_contact) w.pod(*cfg_.mixed_contact);
    w.pod(cfg_.model);
    write_vec3(w, cfg_.gravity);
    w.pod(cfg_.dt);
    w.pod(cfg_.steps_per_collision);
    w.pod(cfg_.skin);
    w.pod(cfg_.neighbor);
    w.pod(cfg_.growth_start);
    w.pod(cfg_.growth_steps);
    // state
    w.pod(dt_);
    w.pod(skin_);
    w.pod(time_);
    w.pod(step_);
    w.pod(started_);
    w.pod(need_rebuild_);
    w.vec(p_.x);
    w.vec(p_.v);
    w.vec(p_.w);
    w.vec(p_.f);
    w.vec(p_.t);
    w.vec(p_.radius);
    w.vec(final_radius_);
    w.vec(p_.mass);
    w.vec(p_.inv_mass);
    w.vec(p_.inv_inertia);
    w.vec(p_.group);
    w.pod(list_.history_size);
    w.vec(list_.first);
    w.vec(list_.partner);
    w.vec(list_.shift);
    w.vec(list_.flags);
    w.vec(list_.hist);
    w.vec(list_.xref);
    w.pod(list_.builds);
    w.vec(wall_hist_);
    w.vec(wall_flags_);
    for (const Vec3& f : wall_force_) write_vec3(w, f);
    os.write(kMagic, sizeof kMagic);  // end marker: a cut file is detected on load
    os.flush();
    if (!os) throw Error("dem: could not write checkpoint " + af.path().string());
  }
  af.commit();
}

Simulation Simulation::load_checkpoint(const std::filesystem::path& file) {
  std::ifstream is(file, std::ios::binary);
  if (!is) throw Error("dem: cannot open checkpoint " + file.string());
  Reader r{is, file.string()};
  char magic[8];
  is.read(magic, sizeof magic);
  if (!is || std::memcmp(magic, kMagic, sizeof kMagic) != 0)
    throw Error("dem: " + file.string() + " is not a grainflow DEM checkpoint (bad magic)");
  Config c;
  read_vec3(r, c.box.lo);
  read_vec3(r, c.box.hi);
  for (bool& b : c.box.periodic) r.pod(b);
  r.pod(c.box.open_top);
  for (Vec3& u : c.box.wall_velocity) read_vec3(r, u);
  std::uint32_t ng = 0;
  r.pod(ng);
  if (ng < 1 || ng > 2) throw Error("dem: checkpoint " + file.string() + " is corrupt (groups)");
  c.groups.resize(ng);
  for (GroupConfig& g : c.groups) {
    r.pod(g.radius);
    r.pod(g.density);
    r.pod(g.contact);
  }
  bool has_mixed = false;
  r.pod(has_mixed);
  if (has_mixed) {
    ContactParams m;
    r.pod(m);
    c.mixed_contact = m;
  }
  r.pod(c.model);
  read_vec3(r, c.gravity);
  r.pod(c.dt);
  r.pod(c.steps_per_collision);
  r.pod(c.skin);
  r.pod(c.neighbor);
  r.pod(c.growth_start);
  r.pod(c.growth_steps);

  Simulation s(std::move(c), Restore{});
  s.configure();
  r.pod(s.dt_);
  r.pod(s.skin_);
  r.pod(s.time_);
  r.pod(s.step_);
  r.pod(s.started_);
  r.pod(s.need_rebuild_);
  r.vec(s.p_.x);
  r.vec(s.p_.v);
  r.vec(s.p_.w);
  r.vec(s.p_.f);
  r.vec(s.p_.t);
  r.vec(s.p_.radius);
  r.vec(s.final_radius_);
  r.vec(s.p_.mass);
  r.vec(s.p_.inv_mass);
  r.vec(s.p_.inv_inertia);
  r.vec(s.p_.group);
  const std::size_t n = s.p_.radius.size();
  s.p_.n = n;
  r.pod(s.list_.history_size);
  r.vec(s.list_.first);
  r.vec(s.list_.partner);
  r.vec(s.list_.shift);
  r.vec(s.list_.flags);
  r.vec(s.list_.hist);
  r.vec(s.list_.xref);
  r.pod(s.list_.builds);
  r.vec(s.wall_hist_);
  r.vec(s.wall_flags_);
  for (Vec3& f : s.wall_force_) read_vec3(r, f);
  is.read(magic, sizeof magic);
  if (!is || std::memcmp(magic, kMagic, sizeof kMagic) != 0)
    throw Error("dem: checkpoint " + file.string() + " is truncated (no end marker)");
  if (s.p_.x.size() != 3 * n || s.p_.f.size() != 3 * n || s.list_.first.size() != n + 1 || s.list_.history_size != s.law_->history_size())
    throw Error("dem: checkpoint " + file.string() + " is inconsistent (array sizes)");
  // Derived arrays: owners, reaches and the cross-pair slots (zero: every pair in range
  // is evaluated again before its slot is read).
  index_pairs(s.list_, s.p_, s.law_->cohesion_range());
  s.update_wall_near();
  return s;
}

}  // namespace grainflow::dem
