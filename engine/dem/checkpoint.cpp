// Checkpoint state of a DEM run (seed 000 §2.2 DUMPREAD/DATASAVE): the full particle state
// at the half step, the Verlet table with every contact's history and the wall contacts'
// history, so that a restored run continues bit for bit. The configuration is rebuilt from
// the scene and only compared: a state saved under another configuration is refused.
#include "engine/core/error.hpp"
#include "engine/dem/simulation.hpp"
#include "engine/io/archive.hpp"

namespace grainflow::dem {

namespace {

void write_vec3(io::ArchiveWriter& w, const Vec3& v) {
  for (int a = 0; a < 3; ++a) w.pod(v[a]);
}

// Every configuration field that shapes the state: equal bytes, same configuration.
std::string config_bytes(const Config& c) {
  io::ArchiveWriter w;
  write_vec3(w, c.box.lo);
  write_vec3(w, c.box.hi);
  for (bool b : c.box.periodic) w.pod(b);
  w.pod(c.box.open_top);
  for (const Vec3& u : c.box.wall_velocity) write_vec3(w, u);
  w.pod(static_cast<std::uint32_t>(c.groups.size()));
  for (const GroupConfig& g : c.groups) {
    w.pod(g.radius);
    w.pod(g.density);
    w.pod(g.contact);
  }
  w.pod(c.mixed_contact.has_value());
  if (c.mixed_contact) w.pod(*c.mixed_contact);
  w.pod(c.model);
  write_vec3(w, c.gravity);
  w.pod(c.dt);
  w.pod(c.steps_per_collision);
  w.pod(c.skin);
  w.pod(c.neighbor);
  w.pod(c.growth_start);
  w.pod(c.growth_steps);
  return w.take();
}

}  // namespace

void Simulation::save_state(io::ArchiveWriter& w) const {
  w.tag("dem.config");
  w.string(config_bytes(cfg_));
  w.tag("dem.state");
  w.pod(dt_);
  w.pod(skin_);
  w.pod(time_);
  w.pod(step_);
  w.pod(started_);
  w.pod(need_rebuild_);
  w.array(p_.x);
  w.array(p_.v);
  w.array(p_.w);
  w.array(p_.f);
  w.array(p_.t);
  w.array(p_.radius);
  w.array(final_radius_);
  w.array(p_.mass);
  w.array(p_.inv_mass);
  w.array(p_.inv_inertia);
  w.array(p_.group);
  w.pod(list_.history_size);
  w.array(list_.first);
  w.array(list_.partner);
  w.array(list_.shift);
  w.array(list_.flags);
  w.array(list_.hist);
  w.array(list_.xref);
  w.pod(list_.builds);
  w.array(wall_hist_);
  w.array(wall_flags_);
  for (const Vec3& f : wall_force_) write_vec3(w, f);
  w.pod(virial_pairs_);
  w.pod(virial_walls_);
}

void Simulation::load_state(io::ArchiveReader& r) {
  r.tag("dem.config");
  if (r.string() != config_bytes(cfg_))
    r.mismatch("the DEM configuration (box, groups, contact model, time step, skin, gravity) differs");
  r.tag("dem.state");
  const std::size_t n = p_.n;
  r.pod(dt_);
  r.pod(skin_);
  r.pod(time_);
  r.pod(step_);
  r.pod(started_);
  r.pod(need_rebuild_);
  r.array_of(p_.x, 3 * n, "positions");
  r.array_of(p_.v, 3 * n, "velocities");
  r.array_of(p_.w, 3 * n, "angular velocities");
  r.array_of(p_.f, 3 * n, "forces");
  r.array_of(p_.t, 3 * n, "torques");
  r.array_of(p_.radius, n, "radii");
  r.array_of(final_radius_, n, "final radii");
  r.array_of(p_.mass, n, "masses");
  r.array_of(p_.inv_mass, n, "inverse masses");
  r.array_of(p_.inv_inertia, n, "inverse inertias");
  r.array_of(p_.group, n, "groups");
  r.pod(list_.history_size);
  if (list_.history_size != law_->history_size()) r.mismatch("contact history of another size");
  r.array_of(list_.first, n + 1, "neighbour table heads");
  r.array(list_.partner);
  r.array_of(list_.shift, list_.partner.size(), "neighbour shifts");
  r.array_of(list_.flags, list_.partner.size(), "neighbour flags");
  r.array_of(list_.hist, list_.partner.size() * list_.history_size, "contact histories");
  r.array(list_.xref);
  r.pod(list_.builds);
  if (list_.first.back() != list_.partner.size()) r.corrupt("the neighbour table's heads do not match its entries");
  r.array(wall_hist_);
  r.array(wall_flags_);
  for (Vec3& f : wall_force_)
    for (int a = 0; a < 3; ++a) r.pod(f[a]);
  r.pod(virial_pairs_);  // the virial of the forces restored above (no pass recomputes them)
  r.pod(virial_walls_);
  // Derived arrays: owners, reaches and the cross-pair slots (zero: every pair in range
  // is evaluated again before its slot is read).
  index_pairs(list_, p_, law_->cohesion_range());
  update_wall_near();
}

}  // namespace grainflow::dem
