#include "scenes/src/engines/particle_snapshot.hpp"

#include <algorithm>
#include <limits>
#include <set>

#include "engine/core/error.hpp"

namespace grainflow::scenes {

std::string default_colour_attribute(const core::ParticleFrame& frame) {
  if (frame.has_velocity()) return "speed";
  if (std::set<int>(frame.type.begin(), frame.type.end()).size() > 1) return "type";
  return "";
}

void frame_bounds(const core::ParticleFrame& frame, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  if (frame.has_box) {
    lo = frame.box_lo;
    hi = frame.box_hi;
    return;
  }
  lo.setConstant(std::numeric_limits<double>::infinity());
  hi = -lo;
  for (std::size_t i = 0; i < frame.size(); ++i) {
    const double r = frame.radius.empty() ? 0.0 : frame.radius[i];
    lo = lo.cwiseMin(frame.position[i] - Eigen::Vector3d::Constant(r));
    hi = hi.cwiseMax(frame.position[i] + Eigen::Vector3d::Constant(r));
  }
  if (frame.size() == 0) {
    lo.setZero();
    hi.setOnes();
  }
}

void to_snapshot(const core::ParticleFrame& frame, const std::string& attribute, render::Snapshot& out) {
  out.dim = frame.dim;
  frame_bounds(frame, out.lo, out.hi);
  out.time = std::isnan(frame.time) ? double(frame.timestep) : frame.time;
  out.pos_radius.resize(frame.size() * 4);
  for (std::size_t i = 0; i < frame.size(); ++i) {
    const auto& p = frame.position[i];
    float* d = &out.pos_radius[4 * i];
    d[0] = float(p.x());
    d[1] = float(p.y());
    d[2] = float(p.z());
    d[3] = float(frame.radius[i]);
  }
  out.periodic = frame.periodic;
  out.attribute.clear();
  out.attribute_name = attribute;
  out.attribute_categorical = attribute == "type" || attribute == "id";
  out.category_names = attribute == "type" ? frame.type_names : std::vector<std::string>{};
  if (attribute.empty()) return;
  const std::vector<double>* column = frame.column(attribute);
  if (!column) {
    std::string names;
    for (const auto& n : frame.column_names()) names += (names.empty() ? "" : ", ") + n;
    throw Error("cannot colour by '" + attribute + "': the file has no such column (it has: " + names + ")");
  }
  out.attribute.assign(column->begin(), column->end());
}

}  // namespace grainflow::scenes
