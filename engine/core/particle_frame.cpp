#include "engine/core/particle_frame.hpp"

#include <cmath>

#include "engine/core/error.hpp"

namespace grainflow::core {

const std::vector<double>* ParticleFrame::column(std::string_view name) const {
  if (auto it = cache_.find(name); it != cache_.end()) return &it->second;
  const std::size_t n = size();
  std::vector<double> v;
  auto from_vec3 = [&](const std::vector<Vec3>& src, int axis) {
    v.resize(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = src[i][axis];
  };
  if (name == "radius") {
    return &radius;
  } else if (name == "diameter") {
    v.resize(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = 2.0 * radius[i];
  } else if (name == "id") {
    v.assign(id.begin(), id.end());
  } else if (name == "type") {
    v.assign(type.begin(), type.end());
  } else if (name == "x" || name == "y" || name == "z") {
    from_vec3(position, name[0] - 'x');
  } else if (has_velocity() && (name == "vx" || name == "vy" || name == "vz")) {
    from_vec3(velocity, name[1] - 'x');
  } else if (has_velocity() && name == "speed") {
    v.resize(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = velocity[i].norm();
  } else {
    for (const auto& [key, values] : extra)
      if (key == name) return &values;
    return nullptr;
  }
  return &cache_.emplace(std::string(name), std::move(v)).first->second;
}

std::vector<std::string> ParticleFrame::column_names() const {
  std::vector<std::string> names{"id", "type", "x", "y", "z", "radius", "diameter"};
  if (has_velocity()) names.insert(names.end(), {"vx", "vy", "vz", "speed"});
  for (const auto& e : extra) names.push_back(e.first);
  return names;
}

void ParticleFrame::clear() {
  dim = 3;
  time = std::numeric_limits<double>::quiet_NaN();
  timestep = -1;
  has_box = false;
  box_lo.setZero();
  box_hi.setZero();
  triclinic = false;
  tilt.setZero();
  periodic = {false, false, false};
  id.clear();
  position.clear();
  radius.clear();
  velocity.clear();
  velocity_columns = false;
  type.clear();
  type_names.clear();
  extra.clear();
  cache_.clear();
}

void ParticleFrame::check_consistent(std::string_view where) const {
  const std::size_t n = size();
  auto bad = [&](std::string_view what, std::size_t got) {
    throw Error(std::string(where) + ": particle frame has " + std::to_string(n) + " positions but " +
                std::to_string(got) + " " + std::string(what));
  };
  if (id.size() != n) bad("ids", id.size());
  if (radius.size() != n) bad("radii", radius.size());
  if (type.size() != n) bad("types", type.size());
  if (!velocity.empty() && velocity.size() != n) bad("velocities", velocity.size());
  for (const auto& [name, values] : extra)
    if (values.size() != n) bad("values of column '" + name + "'", values.size());
  if (dim != 2 && dim != 3) throw Error(std::string(where) + ": dim must be 2 or 3, got " + std::to_string(dim));
}

}  // namespace grainflow::core
