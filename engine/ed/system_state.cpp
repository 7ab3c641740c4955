#include "engine/ed/system_state.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "engine/core/error.hpp"

namespace grainflow::ed {

void SystemState::set_velocity(int i, double vx, double vy) { set_velocity(i, vx, vy, disk[i].w); }

void SystemState::set_velocity(int i, double vx, double vy, double w) {
  synchronise(i);
  Disk& d = disk[i];
  if (slot[i] == SlotState::frozen) {  // a moving wall: outside the books
    d.vx = vx;
    d.vy = vy;
    d.w = w;
    ++counter[i];
    touched_.push_back(i);
    return;
  }
  const double m = d.m;
  kin_ += 0.5 * m * (vx * vx + vy * vy - d.vx * d.vx - d.vy * d.vy);
  rot_ += 0.5 * inertia(i) * (w * w - d.w * d.w);
  px_ += m * (vx - d.vx);
  py_ += m * (vy - d.vy);
  d.vx = vx;
  d.vy = vy;
  d.w = w;
  ++counter[i];
  touched_.push_back(i);
}

void SystemState::recompute_books() {
  kin_ = rot_ = px_ = py_ = mtot_ = 0.0;
  for (int i = 0; i < size(); ++i) {
    if (slot[i] != SlotState::present) continue;
    const Disk& d = disk[i];
    kin_ += 0.5 * d.m * (d.vx * d.vx + d.vy * d.vy);
    rot_ += 0.5 * inertia(i) * d.w * d.w;
    px_ += d.m * d.vx;
    py_ += d.m * d.vy;
    mtot_ += d.m;
  }
}

Observables SystemState::observables() const {
  Observables o;
  o.duration = now_ - stats.t0;
  o.collisions = stats.collisions - stats.collisions0;
  const double n = mobile_count();
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

void SystemState::reset_slots(std::vector<SlotState> states) {
  if (states.empty()) states.assign(size(), SlotState::present);
  slot = std::move(states);
  n_present_ = size();
  n_frozen_ = static_cast<int>(std::count(slot.begin(), slot.end(), SlotState::frozen));
  free_.clear();
  clear_changes();
  event.clear();  // the slots changed wholesale: the loop starts afresh
  events_ready_ = false;
}

void SystemState::add_books(int i, double sign) {
  const Disk& d = disk[i];
  const double m = d.m;
  kin_ += sign * 0.5 * m * (d.vx * d.vx + d.vy * d.vy);
  rot_ += sign * 0.5 * inertia(i) * d.w * d.w;
  px_ += sign * m * d.vx;
  py_ += sign * m * d.vy;
  mtot_ += sign * m;
}

void SystemState::grow() {
  const int n = size();
  const int n1 = n + std::max(64, n / 4);
  disk.resize(n1, Disk{});
  counter.resize(n1, 0u);
  slot.resize(n1, SlotState::absent);
  grid.grow_particles(n1);
  // Event records exist once the loop has started; the timers' records follow the disk slots.
  if (events_ready_) {
    event.insert(event.begin() + n, static_cast<std::size_t>(n1 - n), NextEvent{});
    grown_ = true;
  }
  for (int i = n1 - 1; i >= n; --i) free_.push_back(i);  // lowest id first
}

int SystemState::add_disk(const DiskInit& in) {
  const double x = in.r.x(), y = in.r.y();
  const bool inside = grid.periodic_x() ? (x >= 0.0 && x < grid.lx()) : (x >= 0.0 && x <= grid.lx());
  const bool inside_y = grid.periodic_y() ? (y >= 0.0 && y < grid.ly()) : (y >= 0.0 && y <= grid.ly());
  if (!inside || !inside_y || !std::isfinite(x) || !std::isfinite(y))
    throw Error(fmt::format("ed: a disk added at ({}, {}) lies outside the {} x {} box", x, y, grid.lx(), grid.ly()));
  const double dia = 2.0 * in.radius;
  if (!(dia >= dmin_ * (1.0 - 1e-12) && dia <= dmax_ * (1.0 + 1e-12)) || !(in.mass > 0.0))
    throw Error(fmt::format("ed: a disk added with diameter {} and mass {}; the cell map allows diameters in "
                            "[{}, {}] and the mass must be positive", dia, in.mass, dmin_, dmax_));
  if (free_.empty()) grow();
  const int i = free_.back();
  free_.pop_back();
  disk[i] = Disk{x, y, in.v.x(), in.v.y(), now_, in.radius, in.mass, in.omega};
  ++counter[i];  // predictions that named this slot's former disk are stale
  slot[i] = SlotState::present;
  ++n_present_;
  grid.insert(i, grid.cell_of_point(x, y));
  add_books(i, 1.0);
  ++stats.inserted;
  added_.push_back(i);
  return i;
}

void SystemState::remove_disk(int i) {
  if (slot[i] == SlotState::absent) return;
  if (slot[i] == SlotState::frozen) --n_frozen_;
  else add_books(i, -1.0);
  synchronise(i);
  const int c = grid.cell(i);
  grid.remove(i);
  slot[i] = SlotState::absent;
  --n_present_;
  ++counter[i];  // partners' predictions with it become stale: no collision with the ghost
  if (events_ready_) event[i] = NextEvent{};
  free_.push_back(i);
  ++stats.removed;
  removed_.push_back({i, c});
}

void SystemState::freeze(int i, double vx, double vy) {
  if (slot[i] == SlotState::absent) return;
  synchronise(i);
  if (slot[i] == SlotState::present) {
    add_books(i, -1.0);
    slot[i] = SlotState::frozen;
    ++n_frozen_;
  }
  Disk& d = disk[i];
  d.vx = vx;
  d.vy = vy;
  d.w = 0.0;  // a translating wall: no spin enters a rough collision
  ++counter[i];
  touched_.push_back(i);
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
