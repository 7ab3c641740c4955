#include "engine/ed/system_state.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <stdexcept>
#include <type_traits>

#include <fmt/format.h>

#include "engine/core/error.hpp"
#include "engine/ed/checkpoint.hpp"
#include "engine/io/archive.hpp"

namespace grainflow::ed {

void SystemState::set_velocity(int i, double vx, double vy) { set_velocity(i, vx, vy, body[i].w); }

void SystemState::set_velocity(int i, double vx, double vy, double w) {
  const Disk& d = disk[i];
  DiskBody& b = body[i];
  if (slot[i] != SlotState::frozen) {  // a frozen disk is a moving wall: outside the books
    const double m = b.m;
    kin_ += 0.5 * m * (vx * vx + vy * vy - d.vx * d.vx - d.vy * d.vy);
    rot_ += 0.5 * inertia(i) * (w * w - b.w * b.w);
    px_ += m * (vx - d.vx);
    py_ += m * (vy - d.vy);
    add_kinetic_tensor(m, d.vx, d.vy, vx, vy);
  }
  assign_velocity(i, vx, vy);
  b.w = w;
  ++counter[i];
  touched_.push_back(i);
}

void SystemState::rebase() {
  const double dt = now_ - epoch_;
  if (dt != 0.0) {
    Disk* d = disk.data();
    for (std::size_t i = 0, n = disk.size(); i < n; ++i) {
      d[i].x += d[i].vx * dt;
      d[i].y += d[i].vy * dt;
    }
  }
  epoch_ = now_;
}

void LaneBookLog::settle(const LaneBooks& b) {
  settled_ = Sums{b.kin, b.rot, b.px, b.py, b.kxx, b.kxy, b.kyy, b.kin_t, b.kxx_t, b.kxy_t, b.kyy_t,
                  b.stats.virial, b.stats.virial_xx, b.stats.virial_xy, b.stats.virial_yy};
  events_.clear();
  values_.clear();
  kinds_.clear();
}

void LaneBookLog::reorder_last(LaneBooks& b) {
  // Only the last event is out of place (each earlier one was put in its place in turn).
  const Event last = events_.back();
  std::size_t q = events_.size() - 1;
  while (q > 0 && last.before(events_[q - 1])) --q;
  events_.pop_back();
  events_.insert(events_.begin() + static_cast<std::ptrdiff_t>(q), last);
  const Sums& f = settled_;
  b.kin = f.kin, b.rot = f.rot, b.px = f.px, b.py = f.py, b.kxx = f.kxx, b.kxy = f.kxy, b.kyy = f.kyy;
  b.kin_t = f.kin_t, b.kxx_t = f.kxx_t, b.kxy_t = f.kxy_t, b.kyy_t = f.kyy_t;
  b.stats.virial = f.virial, b.stats.virial_xx = f.virial_xx, b.stats.virial_xy = f.virial_xy,
  b.stats.virial_yy = f.virial_yy;
  // The same calls, with the clock each addition saw, as the lane made them (not logged again).
  const double now = b.now;
  LaneBookLog* const log = b.log;
  b.log = nullptr;
  for (const Event& ev : events_) {
    b.now = ev.now;
    const double* v = values_.data() + ev.values;
    for (std::size_t k = ev.kinds; k < ev.kinds + ev.n_kinds; ++k) {
      if (kinds_[k] == kKinetic) {
        b.add_kinetic(v[0], v[1], v[2], v[3]);
        v += 4;
      } else if (kinds_[k] == kTensor) {
        b.add_tensor(TensorStep{v[0], v[1], v[2]});
        v += 3;
      } else {
        b.add_virial(v[0], v[1], v[2], v[3]);
        v += 4;
      }
    }
  }
  b.now = now;
  b.log = log;
}

void SystemState::absorb_lanes(double t, const LaneBooks* lanes, int n_lanes) {
  advance_clock(t);
  const int n = mobile_count();
  for (int k = 0; k < n_lanes; ++k) {
    const LaneBooks& l = lanes[k];
    const Stats& d = l.stats;
    stats.events += d.events;
    stats.collisions += d.collisions;
    stats.sliding += d.sliding;
    stats.tc_elastic += d.tc_elastic;
    stats.agent_events += d.agent_events;
    stats.cell_crossings += d.cell_crossings;
    stats.stale += d.stale;
    stats.virial += d.virial;
    stats.virial_xx += d.virial_xx;
    stats.virial_xy += d.virial_xy;
    stats.virial_yy += d.virial_yy;
    if (n > 0) stats.kT_integral += (l.kin * t - l.kin_t) / n;
    if (mtot_ > 0.0 && n > 0) {
      stats.kinetic_integral_xx += l.kxx * t - l.kxx_t;
      stats.kinetic_integral_xy += l.kxy * t - l.kxy_t;
      stats.kinetic_integral_yy += l.kyy * t - l.kyy_t;
    }
    add_kinetic(l.kin, l.rot, l.px, l.py);
    kxx_ += l.kxx;
    kxy_ += l.kxy;
    kyy_ += l.kyy;
  }
}

void SystemState::note_body(const DiskBody& b) {
  // The first disk sets the value; one that differs turns it to 0 for good (mixed).
  if (uniform_r_ < 0.0) uniform_r_ = b.r;
  else if (b.r != uniform_r_) uniform_r_ = 0.0;
  if (uniform_m_ < 0.0) uniform_m_ = b.m;
  else if (b.m != uniform_m_) uniform_m_ = 0.0;
}

void SystemState::reset_disks() {
  epoch_ = now_;
  next_rebase_ = stats.events + rebase_period();
  uniform_r_ = uniform_m_ = -1.0;  // no disk yet
  for (int i = 0; i < size(); ++i) note_body(body[i]);
}

void SystemState::recompute_books() {
  kin_ = rot_ = px_ = py_ = mtot_ = 0.0;
  kxx_ = kxy_ = kyy_ = 0.0;
  for (int i = 0; i < size(); ++i) {
    if (slot[i] != SlotState::present) continue;
    const Disk& d = disk[i];
    const double m = body[i].m;
    kin_ += 0.5 * m * (d.vx * d.vx + d.vy * d.vy);
    add_kinetic_tensor(m, 0.0, 0.0, d.vx, d.vy);
    rot_ += 0.5 * inertia(i) * body[i].w * body[i].w;
    px_ += m * d.vx;
    py_ += m * d.vy;
    mtot_ += m;
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
    const double t = o.duration, a = area();
    o.pressure_xx = (stats.kinetic_integral_xx + stats.virial_xx) / t / a;
    o.pressure_xy = (stats.kinetic_integral_xy + stats.virial_xy) / t / a;
    o.pressure_yy = (stats.kinetic_integral_yy + stats.virial_yy) / t / a;
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
  const double m = body[i].m;
  kin_ += sign * 0.5 * m * (d.vx * d.vx + d.vy * d.vy);
  add_kinetic_tensor(sign * m, 0.0, 0.0, d.vx, d.vy);
  rot_ += sign * 0.5 * inertia(i) * body[i].w * body[i].w;
  px_ += sign * m * d.vx;
  py_ += sign * m * d.vy;
  mtot_ += sign * m;
}

void SystemState::grow() {
  const int n = size();
  const int n1 = n + std::max(64, n / 4);
  disk.resize(n1, Disk{});
  body.resize(n1, DiskBody{});
  counter.resize(n1, 0u);
  slot.resize(n1, SlotState::absent);
  tag.resize(n1, 0);
  if (!last_collision.empty()) last_collision.resize(n1, -kNever);
  grid.grow_particles(n1);
  // Event records exist once the loop has started; the timers' records follow the disk slots.
  if (events_ready_) {
    event.insert(event.begin() + n, static_cast<std::size_t>(n1 - n), NextEvent{});
    agent_time.resize(n1, kNever);
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
  // Placed at (x, y) now: at the epoch it would have been v (now − epoch) behind.
  const double dt = now_ - epoch_;
  disk[i] = Disk{x - in.v.x() * dt, y - in.v.y() * dt, in.v.x(), in.v.y()};
  body[i] = DiskBody{in.radius, in.mass, in.omega};
  note_body(body[i]);
  tag[i] = next_tag_++;  // a newcomer, never the id of the slot's former disk
  if (static_cast<std::size_t>(i) < last_collision.size()) last_collision[i] = -kNever;  // a new disk
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
  if (take_out(i)) ++stats.removed;
}

void SystemState::remove_overlapping(int i) {
  if (slot[i] == SlotState::absent) return;
  const Vec2 p = position_now(i);
  take_out(i);
  ++stats.removed_overlap;
  tc.tau += tc.step;
  overlap_log.push_back(OverlapRemoval{now_, p.x(), p.y(), tc.tau, i});
}

bool SystemState::take_out(int i) {
  if (slot[i] == SlotState::absent) return false;
  if (slot[i] == SlotState::frozen) --n_frozen_;
  else add_books(i, -1.0);
  const int c = grid.cell(i);
  grid.remove(i);
  slot[i] = SlotState::absent;
  --n_present_;
  ++counter[i];  // partners' predictions with it become stale: no collision with the ghost
  if (events_ready_) event[i] = NextEvent{};
  free_.push_back(i);
  removed_.push_back({i, c});
  return true;
}

void SystemState::freeze(int i, double vx, double vy) {
  if (slot[i] == SlotState::absent) return;
  if (slot[i] == SlotState::present) {
    add_books(i, -1.0);
    slot[i] = SlotState::frozen;
    ++n_frozen_;
  }
  assign_velocity(i, vx, vy);
  body[i].w = 0.0;  // a translating wall: no spin enters a rough collision
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

// ---- checkpoints ------------------------------------------------------------------------

namespace {

// NextEvent as written, with the agent event's time (SystemState::agent_time; kNever when
// the event is not an agent's): its bit fields as whole bytes and its padding explicit and
// zero, so that the same records always give the same bytes whatever the compiler's layout.
struct PackedEvent {
  double key, agent_time;
  std::int32_t partner;
  std::uint32_t partner_count;
  std::uint8_t kind, cross_dir, crossing, pad[5];
};
static_assert(sizeof(PackedEvent) == 32 && std::is_trivially_copyable_v<PackedEvent>);
// Written as raw bytes, so they must have no padding (a new field: check, then update).
static_assert(sizeof(Disk) == 4 * sizeof(double) && sizeof(DiskBody) == 3 * sizeof(double));
static_assert(sizeof(Stats) == 21 * 8, "Stats is written as raw bytes: a new field must not add padding");
static_assert(sizeof(SystemState::Removal) == 2 * sizeof(int));
static_assert(sizeof(OverlapRemoval) == 5 * 8 && std::is_trivially_copyable_v<OverlapRemoval>);

}  // namespace

void SystemState::reschedule(const TimerAgent* t) {
  for (std::size_t a = 0; a < timers.size(); ++a)
    if (timers[a].get() == t) {
      rescheduled_.push_back(static_cast<int>(a));
      return;
    }
  throw std::logic_error("SystemState::reschedule: not a timer of this simulation");
}

void SystemState::save(io::ArchiveWriter& w) const {
  // Nothing records a pending reschedule: the loop settles them within the action.
  if (!rescheduled_.empty()) throw std::logic_error("SystemState::save with timers to reschedule pending");
  w.tag("ed.state");
  w.pod(now_);
  w.pod(kin_);
  w.pod(rot_);
  w.pod(px_);
  w.pod(py_);
  w.pod(mtot_);
  w.pod(kxx_);
  w.pod(kxy_);
  w.pod(kyy_);
  w.pod(dmin_);
  w.pod(dmax_);
  w.pod(static_cast<std::int32_t>(n_present_));
  w.pod(static_cast<std::int32_t>(n_frozen_));
  w.flag(grown_);
  w.flag(events_ready_);
  w.pod(stats);
  w.pod(epoch_);
  w.pod(uniform_r_);
  w.pod(uniform_m_);
  w.pod(next_rebase_);
  w.array(disk);
  w.array(body);
  w.array(counter);
  w.array(slot);
  std::vector<PackedEvent> ev(event.size());
  for (std::size_t e = 0; e < event.size(); ++e) {
    const NextEvent& x = event[e];
    PackedEvent& p = ev[e];
    p = PackedEvent{};
    p.key = x.key;
    p.agent_time = e < agent_time.size() && x.kind == EventKind::Agent ? agent_time[e] : kNever;
    p.partner = static_cast<std::int32_t>(x.partner);
    p.partner_count = x.partner_count;
    p.kind = static_cast<std::uint8_t>(x.kind);
    p.cross_dir = x.cross_dir;
    p.crossing = x.crossing ? 1 : 0;
  }
  w.array(ev);
  w.array(free_);
  w.array(touched_);
  w.array(added_);
  w.array(removed_);
  w.tag("ed.tc");
  w.pod(rule.e);
  w.pod(tc.tau);
  w.pod(tc.step);
  w.array(last_collision);
  w.array(overlap_log);
  w.tag("ed.tags");
  w.array(tag);
  w.pod(next_tag_);
  w.tag("ed.cells");
  grid.save_members(w);
}

SystemState::Saved SystemState::read_saved(io::ArchiveReader& r) const {
  r.tag("ed.state");
  Saved s;
  r.pod(s.now);
  r.pod(s.kin);
  r.pod(s.rot);
  r.pod(s.px);
  r.pod(s.py);
  r.pod(s.mtot);
  r.pod(s.kxx);
  r.pod(s.kxy);
  r.pod(s.kyy);
  r.pod(s.dmin);
  r.pod(s.dmax);
  s.n_present = r.get<std::int32_t>();
  s.n_frozen = r.get<std::int32_t>();
  s.grown = r.flag("the grown flag");
  s.events_ready = r.flag("the events-ready flag");
  r.pod(s.stats);
  r.pod(s.epoch);
  r.pod(s.uniform_r);
  r.pod(s.uniform_m);
  r.pod(s.next_rebase);
  if (!(s.epoch <= s.now) || !(s.uniform_r >= 0.0 || s.uniform_r == -1.0) ||
      !(s.uniform_m >= 0.0 || s.uniform_m == -1.0))
    r.corrupt(fmt::format("the disks' epoch {} is after the clock {}, or the uniform radius and mass are {} and {}",
                          s.epoch, s.now, s.uniform_r, s.uniform_m));
  r.array(s.disk);
  const std::size_t n = s.disk.size();
  r.array_of(s.body, n, "the disk bodies (radius, mass, spin)");
  if (n > static_cast<std::size_t>(INT32_MAX)) r.corrupt(fmt::format("{} disk slots", n));
  const int ni = static_cast<int>(n);
  r.array_of(s.counter, n, "the disk counters");
  r.array_of(s.slot, n, "the slot states");
  if (!s.events_ready) r.corrupt("the event records were never filled (the event loop had not started)");
  std::vector<PackedEvent> ev;
  r.array_of(ev, n + timers.size(), "the event records (disk slots, then timers)");
  r.array(s.free);
  r.array(s.touched);
  r.array(s.added);
  r.array(s.removed);
  r.tag("ed.tc");
  r.pod(s.e);
  r.pod(s.tc.tau);
  r.pod(s.tc.step);
  r.array(s.last_collision);
  r.array(s.overlap_log);
  if (!(s.e >= 0.0 && s.e <= 1.0) || !(s.tc.tau >= 0.0) || !(s.tc.step >= 0.0))
    r.corrupt(fmt::format("the TC model has e = {}, tau_tc = {}, tau_tc_step = {}", s.e, s.tc.tau, s.tc.step));
  if (!s.last_collision.empty() && s.last_collision.size() != n)
    r.corrupt(fmt::format("{} last-collision times for {} disk slots", s.last_collision.size(), n));
  r.tag("ed.tags");
  r.array_of(s.tag, n, "the persistent ids (tags)");
  r.pod(s.next_tag);
  r.tag("ed.cells");
  s.cells = grid.read_members(r, ni);

  // Consistency: anything an index is taken from must point inside its array.
  {
    // Every disk present has its own id, below the next one to give.
    std::vector<std::int64_t> tags;
    for (std::size_t i = 0; i < n; ++i) {
      if (s.slot[i] == SlotState::absent) continue;
      if (s.tag[i] <= 0 || s.tag[i] >= s.next_tag)
        r.corrupt(fmt::format("disk {} has id {}, outside 1 .. {}", i, s.tag[i], s.next_tag - 1));
      tags.push_back(s.tag[i]);
    }
    std::sort(tags.begin(), tags.end());
    if (auto d = std::adjacent_find(tags.begin(), tags.end()); d != tags.end())
      r.corrupt(fmt::format("two disks have id {}", *d));
  }
  int present = 0, frozen = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto v = static_cast<std::uint8_t>(s.slot[i]);
    if (v > 2) r.corrupt(fmt::format("slot {} has state {}", i, v));
    present += v != 0;
    frozen += v == 2;
  }
  if (present != s.n_present || frozen != s.n_frozen)
    r.corrupt(fmt::format("{} disks present and {} frozen are recorded, the slot states hold {} and {}",
                          s.n_present, s.n_frozen, present, frozen));
  std::vector<char> seen(n, 0);
  if (s.free.size() != n - static_cast<std::size_t>(present))
    r.corrupt(fmt::format("the free-slot list has {} entries for {} empty slots", s.free.size(),
                          n - static_cast<std::size_t>(present)));
  for (int i : s.free) {
    if (i < 0 || i >= ni || s.slot[i] != SlotState::absent || seen[i])
      r.corrupt(fmt::format("the free-slot list names slot {}, which is not a distinct empty slot", i));
    seen[i] = 1;
  }
  for (int i : s.touched)
    if (i < 0 || i >= ni) r.corrupt(fmt::format("a pending re-prediction names slot {} of {}", i, n));
  for (int i : s.added)
    if (i < 0 || i >= ni) r.corrupt(fmt::format("a pending insertion names slot {} of {}", i, n));
  for (const Removal& x : s.removed)
    if (x.id < 0 || x.id >= ni || x.cell < 0 || x.cell >= grid.size())
      r.corrupt(fmt::format("a pending removal names slot {} in cell {}", x.id, x.cell));
  s.event.resize(ev.size());
  s.agent_time.assign(n, kNever);
  for (std::size_t e = 0; e < ev.size(); ++e) {
    const PackedEvent& p = ev[e];
    if (p.kind > 2 || p.cross_dir > 3 || p.crossing > 1)
      r.corrupt(fmt::format("event record {} has kind {}, direction {}, crossing flag {}", e, p.kind, p.cross_dir,
                            p.crossing));
    const auto kind = static_cast<EventKind>(p.kind);
    if (e < n && ((kind == EventKind::Pair && (p.partner < 0 || p.partner >= ni)) ||
                  (kind == EventKind::Agent &&
                   (p.partner < 0 || static_cast<std::size_t>(p.partner) >= agents.size()))))
      r.corrupt(fmt::format("event record {} names partner {} ({} slots, {} agents)", e, p.partner, n,
                            agents.size()));
    NextEvent& x = s.event[e];
    x.key = p.key;
    if (e < n && kind == EventKind::Agent) s.agent_time[e] = p.agent_time;
    x.partner = kind == EventKind::None ? 0u : static_cast<std::uint32_t>(p.partner);
    x.partner_count = p.partner_count;
    x.kind = kind;
    x.cross_dir = p.cross_dir;
    x.crossing = p.crossing != 0;
  }
  // The cell map holds exactly the disks present, each where its cell entry says.
  const int nc = grid.size(), stride = grid.capacity() + 1;
  const auto& slots = s.cells.slots;
  long long members = 0;
  for (int c = 0; c < nc; ++c) {
    const int k = slots[static_cast<std::size_t>(c) * stride];
    if (k < 0 || k > grid.capacity()) r.corrupt(fmt::format("cell {} holds {} disks", c, k));
    members += k;
  }
  if (members != present) r.corrupt(fmt::format("the cells hold {} disks, {} are present", members, present));
  for (std::size_t i = 0; i < n; ++i) {
    const int c = s.cells.cell[i];
    if (s.slot[i] == SlotState::absent) {
      if (c != -1) r.corrupt(fmt::format("empty slot {} is listed in cell {}", i, c));
      continue;
    }
    const int p = s.cells.pos[i];
    if (c < 0 || c >= nc || p < 0 || p >= slots[static_cast<std::size_t>(c) * stride] ||
        slots[static_cast<std::size_t>(c) * stride + 1 + p] != static_cast<std::int32_t>(i))
      r.corrupt(fmt::format("disk {} is not where the cell map says (cell {}, place {})", i, c, p));
  }
  return s;
}

void SystemState::restore(Saved&& s) noexcept {
  now_ = s.now;
  kin_ = s.kin;
  rot_ = s.rot;
  px_ = s.px;
  py_ = s.py;
  mtot_ = s.mtot;
  kxx_ = s.kxx;
  kxy_ = s.kxy;
  kyy_ = s.kyy;
  dmin_ = s.dmin;
  dmax_ = s.dmax;
  n_present_ = s.n_present;
  n_frozen_ = s.n_frozen;
  grown_ = s.grown;
  events_ready_ = s.events_ready;
  stats = s.stats;
  epoch_ = s.epoch;
  uniform_r_ = s.uniform_r;
  uniform_m_ = s.uniform_m;
  next_rebase_ = s.next_rebase;
  disk.swap(s.disk);
  body.swap(s.body);
  counter.swap(s.counter);
  slot.swap(s.slot);
  event.swap(s.event);
  agent_time.swap(s.agent_time);
  free_.swap(s.free);
  touched_.swap(s.touched);
  added_.swap(s.added);
  removed_.swap(s.removed);
  grid.adopt_members(std::move(s.cells));
  rule.e = s.e;
  tc = s.tc;
  last_collision.swap(s.last_collision);
  overlap_log.swap(s.overlap_log);
  tag.swap(s.tag);
  next_tag_ = s.next_tag;
}

// Field for field what restore() takes back (a new field of Saved: both).
void SystemState::snapshot(Saved& s) const {
  s.now = now_;
  s.kin = kin_;
  s.rot = rot_;
  s.px = px_;
  s.py = py_;
  s.mtot = mtot_;
  s.kxx = kxx_;
  s.kxy = kxy_;
  s.kyy = kyy_;
  s.dmin = dmin_;
  s.dmax = dmax_;
  s.n_present = n_present_;
  s.n_frozen = n_frozen_;
  s.grown = grown_;
  s.events_ready = events_ready_;
  s.stats = stats;
  s.epoch = epoch_;
  s.uniform_r = uniform_r_;
  s.uniform_m = uniform_m_;
  s.next_rebase = next_rebase_;
  s.disk = disk;
  s.body = body;
  s.counter = counter;
  s.slot = slot;
  s.event = event;
  s.agent_time = agent_time;
  s.free = free_;
  s.touched = touched_;
  s.added = added_;
  s.removed = removed_;
  grid.copy_members(s.cells);
  s.e = rule.e;
  s.tc = tc;
  s.last_collision = last_collision;
  s.overlap_log = overlap_log;
  s.tag = tag;
  s.next_tag = next_tag_;
}

}  // namespace grainflow::ed
