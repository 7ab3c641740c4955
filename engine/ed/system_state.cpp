#include "engine/ed/system_state.hpp"

#include <algorithm>

namespace grainflow::ed {

void SystemState::set_velocity(int i, double vx, double vy) { set_velocity(i, vx, vy, omega[i]); }

void SystemState::set_velocity(int i, double vx, double vy, double w) {
  synchronise(i);
  Disk& d = disk[i];
  const double m = mass[i];
  kin_ += 0.5 * m * (vx * vx + vy * vy - d.vx * d.vx - d.vy * d.vy);
  rot_ += 0.5 * inertia(i) * (w * w - omega[i] * omega[i]);
  px_ += m * (vx - d.vx);
  py_ += m * (vy - d.vy);
  d.vx = vx;
  d.vy = vy;
  omega[i] = w;
  ++counter[i];
  touched_.push_back(i);
}

void SystemState::recompute_books() {
  kin_ = rot_ = px_ = py_ = mtot_ = 0.0;
  for (int i = 0; i < size(); ++i) {
    const Disk& d = disk[i];
    kin_ += 0.5 * mass[i] * (d.vx * d.vx + d.vy * d.vy);
    rot_ += 0.5 * inertia(i) * omega[i] * omega[i];
    px_ += mass[i] * d.vx;
    py_ += mass[i] * d.vy;
    mtot_ += mass[i];
  }
}

Observables SystemState::observables() const {
  Observables o;
  o.duration = now_ - stats.t0;
  o.collisions = stats.collisions - stats.collisions0;
  const double n = size();
  if (o.duration > 0.0 && n > 0) {
    o.kT = stats.kT_integral / o.duration;
    // 2D collision virial (Allen & Tildesley 1987, §3.7; Alder & Wainwright 1960):
    // P A = N <kT> + (1/(2 t)) Σ_collisions r_ij · Δp_i.
    o.pressure = (n * o.kT + stats.virial / (2.0 * o.duration)) / area();
    o.compressibility = o.kT > 0.0 ? o.pressure * area() / (n * o.kT) : 0.0;
    o.collision_rate = 2.0 * static_cast<double>(o.collisions) / (n * o.duration);
    o.mean_free_time = o.collisions ? 1.0 / o.collision_rate : kNever;
  }
  return o;
}

void SystemState::index_agents() {
  const int nc = grid.size();
  std::vector<std::vector<std::int32_t>> per(nc);
  std::vector<int> cells;
  for (std::size_t a = 0; a < agents.size(); ++a) {
    cells.clear();
    agents[a]->cells(grid, cells);
    std::sort(cells.begin(), cells.end());
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    for (int c : cells) per[c].push_back(static_cast<std::int32_t>(a));
  }
  cell_agent_begin.assign(nc + 1, 0);
  cell_agents.clear();
  for (int c = 0; c < nc; ++c) {
    cell_agent_begin[c] = static_cast<std::int32_t>(cell_agents.size());
    cell_agents.insert(cell_agents.end(), per[c].begin(), per[c].end());
  }
  cell_agent_begin[nc] = static_cast<std::int32_t>(cell_agents.size());
}

}  // namespace grainflow::ed
