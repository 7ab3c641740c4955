#include "engine/ed/simulation.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>
#include <thread>
#include <utility>

#include <fmt/format.h>

#include "engine/core/error.hpp"
#include "engine/ed/bucket_calendar.hpp"
#include "engine/ed/cell_heap_calendar.hpp"
#include "engine/ed/elastic_walls.hpp"
#include "engine/ed/parallel_loop.hpp"

namespace grainflow::ed {

std::string_view calendar_name(CalendarKind k) {
  return k == CalendarKind::cell_heap ? "cell_heap" : "bucket";
}

CalendarKind calendar_from_name(std::string_view name) {
  if (name == "cell_heap") return CalendarKind::cell_heap;
  if (name == "bucket") return CalendarKind::bucket;
  throw Error(fmt::format("ed: calendar \"{}\" is unknown; allowed: \"cell_heap\", \"bucket\"", name));
}

namespace {
void check_config(const Config& c) {
  auto bad = [](std::string_view key, double v, std::string_view allowed) {
    throw Error(fmt::format("ed: {} = {} is invalid; allowed: {}", key, v, allowed));
  };
  if (!(c.lx > 0.0) || !std::isfinite(c.lx)) bad("lx", c.lx, "a positive length");
  if (!(c.ly > 0.0) || !std::isfinite(c.ly)) bad("ly", c.ly, "a positive length");
  if (c.n < 0) bad("n", c.n, "n >= 0");
  if (c.n == 0 && !(c.area_fraction > 0.0 && c.area_fraction < 0.9069))
    bad("area_fraction", c.area_fraction, "0 < area_fraction < 0.9069 (close packing)");
  if (!(c.kT >= 0.0) || !std::isfinite(c.kT)) bad("kT", c.kT, "kT >= 0");
  if (!(c.e >= 0.0 && c.e <= 1.0)) bad("e", c.e, "0 <= e <= 1");
  if (!(c.e_t >= -1.0 && c.e_t <= 1.0)) bad("e_t", c.e_t, "-1 <= e_t <= 1");
  if (!(c.mu >= 0.0)) bad("mu", c.mu, "mu >= 0 (infinity: no sliding)");
  if (!(c.tau_tc >= 0.0) || !std::isfinite(c.tau_tc)) bad("tau_tc", c.tau_tc, "tau_tc >= 0 (0: no cutoff)");
  if (!(c.tau_tc_step >= 0.0) || !std::isfinite(c.tau_tc_step))
    bad("tau_tc_step", c.tau_tc_step, "tau_tc_step >= 0");
  if (c.open_x && c.periodic_x) bad("open_x", 1, "open_x only with periodic_x = false");
  if (!(c.wall_restitution >= 0.0 && c.wall_restitution <= 1.0))
    bad("wall_restitution", c.wall_restitution, "0 <= wall_restitution <= 1");
}
}  // namespace

Simulation::Simulation(const Config& cfg) : cfg_(cfg) {
  check_config(cfg_);
  const int n = cfg_.n > 0 ? cfg_.n
                           : static_cast<int>(std::lround(cfg_.area_fraction * cfg_.lx * cfg_.ly /
                                                          (std::numbers::pi / 4.0)));
  core::Rng rng(cfg_.seed);
  auto disks = triangular_lattice(n, 1.0, cfg_.lx, cfg_.ly, cfg_.periodic_x, cfg_.periodic_y, rng);
  maxwell_velocities(disks, cfg_.kT, cfg_.stream, cfg_.mu > 0.0, 0.5, rng);
  build(std::move(disks));
}

Simulation::Simulation(const Config& cfg, std::vector<DiskInit> disks) : cfg_(cfg) {
  check_config(cfg_);
  build(std::move(disks));
}

Simulation::~Simulation() = default;

void Simulation::build(std::vector<DiskInit> disks) {
  const int n = static_cast<int>(disks.size());
  n_built_ = n;
  double dmax = 0.0, dmin = kNever;
  for (int i = 0; i < n; ++i) {
    const DiskInit& d = disks[i];
    if (!(d.radius > 0.0) || !(d.mass > 0.0))
      throw Error(fmt::format("ed: disk {} has radius {} and mass {}; both must be positive", i, d.radius, d.mass));
    const bool inx = cfg_.periodic_x ? (d.r.x() >= 0.0 && d.r.x() < cfg_.lx)
                                     : (d.r.x() >= d.radius && d.r.x() <= cfg_.lx - d.radius);
    const bool iny = cfg_.periodic_y ? (d.r.y() >= 0.0 && d.r.y() < cfg_.ly)
                                     : (d.r.y() >= d.radius && d.r.y() <= cfg_.ly - d.radius);
    if (!inx || !iny)
      throw Error(fmt::format("ed: disk {} at ({}, {}) with radius {} is outside the {} x {} box", i,
                              d.r.x(), d.r.y(), d.radius, cfg_.lx, cfg_.ly));
    dmax = std::max(dmax, 2.0 * d.radius);
    dmin = std::min(dmin, 2.0 * d.radius);
  }
  if (cfg_.min_cell_size < dmax)
    throw Error(fmt::format("ed: min_cell_size = {} is smaller than the largest diameter {}; cells "
                            "must be at least one diameter (seed 003 §2.2)", cfg_.min_cell_size, dmax));
  s_.grid = CellGrid(cfg_.lx, cfg_.ly, cfg_.periodic_x, cfg_.periodic_y, cfg_.min_cell_size,
                     n > 0 ? dmin : 1.0);
  s_.rule = CollisionParams{cfg_.e, cfg_.e_t, cfg_.mu, 0.5};
  s_.tc = TimeCutoff{cfg_.tau_tc, cfg_.tau_tc_step};
  s_.disk.resize(n);
  s_.body.resize(n);
  s_.counter.assign(n, 0);
  s_.grid.resize_particles(n);
  for (int i = 0; i < n; ++i) {
    const DiskInit& d = disks[i];
    s_.disk[i] = Disk{d.r.x(), d.r.y(), d.v.x(), d.v.y()};
    s_.body[i] = DiskBody{d.radius, d.mass, d.omega};
    s_.grid.insert(i, s_.grid.cell_of_point(d.r.x(), d.r.y()));
  }
  s_.reset_slots();
  s_.reset_disks();
  assign_tags(disks);
  // Overlaps are an impossible configuration, not something to resolve silently.
  const double gap = min_gap();
  if (gap < -1e-9 * std::max(1.0, dmax))
    throw Error(fmt::format("ed: initial disks overlap (smallest gap {}); place them at least a "
                            "diameter apart", gap));
  s_.set_diameter_range(n > 0 ? dmin : 1.0, std::min(s_.grid.width(), s_.grid.height()));
  s_.recompute_books();
  const bool walls_x = !cfg_.periodic_x && !cfg_.open_x;
  if (walls_x || !cfg_.periodic_y)
    s_.agents.push_back(std::make_unique<ElasticWalls>(cfg_.lx, cfg_.ly, walls_x, !cfg_.periodic_y,
                                                       cfg_.wall_restitution));
  if (cfg_.lanes == 2) {
    if (cfg_.calendar != CalendarKind::bucket) throw Error("ed: two lanes run with the bucket calendar only");
    loop_ = std::make_unique<ParallelLoop>(s_, cfg_.threads);
  } else if (cfg_.lanes != 1 || cfg_.threads != 1) {
    throw Error(fmt::format("ed: lanes = {}, threads = {}: allowed lanes 1 (threads 1) or 2 (threads 1 or 2)",
                            cfg_.lanes, cfg_.threads));
  } else if (cfg_.calendar == CalendarKind::cell_heap)
    loop_ = std::make_unique<EventLoop<CellHeapCalendar>>(s_);
  else
    loop_ = std::make_unique<EventLoop<BucketCalendar>>(s_);
  restart();
  s_.reset_measurements();
}

namespace {
std::atomic<int> g_lane_threads{0};  // 0: as the machine has cores
}  // namespace

int lane_threads() {
  const int n = g_lane_threads.load(std::memory_order_relaxed);
  if (n > 0) return std::min(n, 2);
  return std::thread::hardware_concurrency() >= 2 ? 2 : 1;
}
void set_lane_threads(int n) { g_lane_threads.store(n, std::memory_order_relaxed); }

// The disks' persistent ids: 1, 2, … in order, or the ones given (all or none, distinct,
// positive); the next disk added gets one more than the largest.
void Simulation::assign_tags(const std::vector<DiskInit>& disks) {
  const std::size_t n = disks.size();
  const std::size_t given =
      static_cast<std::size_t>(std::count_if(disks.begin(), disks.end(), [](const DiskInit& d) { return d.tag != 0; }));
  std::vector<std::int64_t> tags(n);
  if (given == 0) {
    for (std::size_t i = 0; i < n; ++i) tags[i] = static_cast<std::int64_t>(i) + 1;
    s_.reset_tags(std::move(tags), static_cast<std::int64_t>(n) + 1);
    return;
  }
  if (given != n)
    throw Error(fmt::format("ed: {} of {} disks have an id; give every disk one or none", given, n));
  std::vector<std::pair<std::int64_t, std::size_t>> sorted(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (disks[i].tag < 0)
      throw Error(fmt::format("ed: disk {} has id {}; allowed: a positive id", i, disks[i].tag));
    tags[i] = disks[i].tag;
    sorted[i] = {disks[i].tag, i};
  }
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t k = 1; k < n; ++k)
    if (sorted[k].first == sorted[k - 1].first)
      throw Error(fmt::format("ed: disks {} and {} have the same id {}; allowed: distinct ids", sorted[k - 1].second,
                              sorted[k].second, sorted[k].first));
  s_.reset_tags(std::move(tags), n ? sorted.back().first + 1 : 1);
}

void Simulation::restart() {
  s_.index_agents();
  loop_->start();
}

ParticleAgent* Simulation::add_agent(std::unique_ptr<ParticleAgent> agent) {
  s_.agents.push_back(std::move(agent));
  restart();
  return s_.agents.back().get();
}

TimerAgent* Simulation::add_timer(std::unique_ptr<TimerAgent> timer) {
  s_.timers.push_back(std::move(timer));
  restart();
  return s_.timers.back().get();
}

void Simulation::compact(const std::vector<int>& kept) {
  // `kept` may be any order of distinct present ids: gathered through copies.
  const int n = static_cast<int>(kept.size());
  std::vector<SlotState> states(n);
  std::vector<Disk> disks(static_cast<std::size_t>(n));
  std::vector<DiskBody> bodies(static_cast<std::size_t>(n));
  std::vector<std::uint32_t> counters(static_cast<std::size_t>(n));
  std::vector<double> last(s_.last_collision.empty() ? 0 : static_cast<std::size_t>(n));
  std::vector<std::int64_t> tags(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    const int i = kept[k];
    disks[k] = s_.disk[i];
    bodies[k] = s_.body[i];
    counters[k] = s_.counter[i];
    states[k] = s_.slot[i];
    tags[k] = s_.tag[i];  // the disk keeps its id in its new slot
    if (!last.empty()) last[k] = s_.last_collision[i];
  }
  s_.last_collision = std::move(last);
  s_.reset_tags(std::move(tags), s_.next_tag());
  s_.disk.assign(disks.begin(), disks.end());
  s_.body.assign(bodies.begin(), bodies.end());
  s_.counter.assign(counters.begin(), counters.end());
  s_.grid = CellGrid(s_.grid.lx(), s_.grid.ly(), s_.grid.periodic_x(), s_.grid.periodic_y(),
                     cfg_.min_cell_size, std::max(1e-12, [&] {
                       double d = kNever;
                       for (const DiskBody& x : s_.body) d = std::min(d, 2.0 * x.r);
                       return n ? d : 1.0;
                     }()));
  s_.grid.resize_particles(n);
  // The caller synchronised: the records hold the positions now.
  for (int i = 0; i < n; ++i) s_.grid.insert(i, s_.grid.cell_of_point(s_.disk[i].x, s_.disk[i].y));
  s_.reset_slots(std::move(states));
  s_.reset_disks();
  {
    double dmin = kNever;
    for (const DiskBody& x : s_.body) dmin = std::min(dmin, 2.0 * x.r);
    s_.set_diameter_range(n ? dmin : 1.0, std::min(s_.grid.width(), s_.grid.height()));
  }
  s_.recompute_books();
  restart();
}

void Simulation::reorder_disks(const std::vector<int>& order) {
  std::vector<char> seen(static_cast<std::size_t>(s_.size()), 0);
  for (int i : order) {
    if (i < 0 || i >= s_.size() || !s_.present(i) || seen[static_cast<std::size_t>(i)])
      throw Error(fmt::format("ed: reorder_disks: id {} is not a disk present, or comes twice", i));
    seen[static_cast<std::size_t>(i)] = 1;
  }
  if (static_cast<int>(order.size()) != s_.count())
    throw Error(fmt::format("ed: reorder_disks: {} ids given for {} disks present", order.size(), s_.count()));
  synchronise();  // cells are rebuilt from positions, which must be current
  compact(order);
}

std::vector<int> Simulation::cell_order() const {
  std::vector<int> order;
  order.reserve(static_cast<std::size_t>(s_.count()));
  for (int c = 0; c < s_.grid.size(); ++c) {
    const std::size_t first = order.size();
    for (int k = 0; k < s_.grid.count(c); ++k) order.push_back(s_.grid.member(c, k));
    std::sort(order.begin() + static_cast<std::ptrdiff_t>(first), order.end());
  }
  return order;
}

ElasticWalls* Simulation::walls() {
  for (auto& a : s_.agents)
    if (auto* w = dynamic_cast<ElasticWalls*>(a.get())) return w;
  return nullptr;
}

const ElasticWalls* Simulation::walls() const { return const_cast<Simulation*>(this)->walls(); }

CircularObstacle& Simulation::add_obstacle(const ObstacleConfig& o) {
  const double margin = std::max(s_.grid.width(), s_.grid.height());
  const Vec2 c = o.centre;
  if (!(o.radius > 0.0) || c.x() - o.radius - margin < 0.0 || c.x() + o.radius + margin > cfg_.lx ||
      c.y() - o.radius - margin < 0.0 || c.y() + o.radius + margin > cfg_.ly)
    throw Error(fmt::format("ed: obstacle at ({}, {}) with radius {} must lie inside the {} x {} box with a "
                            "margin of one cell ({})", c.x(), c.y(), o.radius, cfg_.lx, cfg_.ly, margin));
  if (!(o.restitution >= 0.0 && o.restitution <= 1.0))
    throw Error(fmt::format("ed: obstacle restitution = {} is invalid; allowed: 0 <= r <= 1", o.restitution));
  if (!(o.kT > 0.0)) throw Error(fmt::format("ed: obstacle kT = {} is invalid; it must be positive", o.kT));
  remove_disks_unless([&](int i) {
    const Vec2 p = s_.position_now(i);
    return std::hypot(p.x() - c.x(), p.y() - c.y()) >= o.radius + s_.body[i].r;
  });
  return static_cast<CircularObstacle&>(*add_agent(std::make_unique<CircularObstacle>(o)));
}

void Simulation::run_until(double t) {
  if (t < s_.now())
    throw Error(fmt::format("ed: run_until({}) is before the current time {}", t, s_.now()));
  loop_->run_until(t);
}

bool Simulation::run_until(double t, std::uint64_t max_events) {
  if (t < s_.now())
    throw Error(fmt::format("ed: run_until({}) is before the current time {}", t, s_.now()));
  return loop_->run_until(t, max_events);
}

std::uint64_t Simulation::advance(std::uint64_t events) { return loop_->advance(events); }

void Simulation::set_restitution(double e) {
  if (!(e >= 0.0 && e <= 1.0))
    throw Error(fmt::format("ed: set_restitution({}) is invalid; allowed: 0 <= e <= 1", e));
  s_.rule.e = e;
}

void Simulation::set_time_cutoff(double tau_tc, double tau_tc_step) {
  if (!(tau_tc >= 0.0) || !std::isfinite(tau_tc) || !(tau_tc_step >= 0.0) || !std::isfinite(tau_tc_step))
    throw Error(fmt::format("ed: set_time_cutoff({}, {}) is invalid; allowed: tau_tc >= 0, tau_tc_step >= 0",
                            tau_tc, tau_tc_step));
  s_.tc = TimeCutoff{tau_tc, tau_tc_step};
}

bool CollapseGuard::collapsed(const Simulation& sim) {
  const std::uint64_t events = sim.stats().events;
  if (window_ == 0 || events < events0_ + window_) return false;
  const double t = sim.time();
  const double dt = t - t0_;
  const double dn = double(events - events0_);
  rate_ = dt > 0.0 ? dn / dt : kNever;
  average_ = t > 0.0 ? double(events) / t : kNever;
  events0_ = events;
  t0_ = t;
  // Slower than `ratio` of the average: dt < ratio · dn · (t / events).
  return dt < ratio_ * dn * (t / double(events));
}

void Simulation::synchronise() { s_.rebase(); }

double Simulation::kinetic_energy() const {
  double k = 0.0;
  for (int i = 0; i < s_.size(); ++i) {
    if (s_.slot[i] != SlotState::present) continue;
    const Disk& d = s_.disk[i];
    const DiskBody& b = s_.body[i];
    k += 0.5 * b.m * (d.vx * d.vx + d.vy * d.vy) + 0.5 * s_.inertia(i) * b.w * b.w;
  }
  return k;
}

Vec2 Simulation::momentum() const {
  Vec2 p{0.0, 0.0};
  for (int i = 0; i < s_.size(); ++i)
    if (s_.slot[i] == SlotState::present) p += s_.body[i].m * Vec2{s_.disk[i].vx, s_.disk[i].vy};
  return p;
}

double Simulation::area_fraction() const {
  double a = 0.0;
  for (int i = 0; i < s_.size(); ++i)
    if (s_.present(i)) a += std::numbers::pi * s_.body[i].r * s_.body[i].r;
  return a / s_.area();
}

double Simulation::min_gap() const {
  // Uses the cell lists: every pair closer than a cell is in adjacent cells.
  const CellGrid& g = s_.grid;
  double gap = kNever;
  for (int i = 0; i < s_.size(); ++i) {
    if (!s_.present(i)) continue;
    const Vec2 pi = s_.position_now(i);
    const int c = g.cell(i);
    for (int ky = -1; ky <= 1; ++ky)
      for (int kx = -1; kx <= 1; ++kx) {
        int cx = g.ix(c) + kx, cy = g.iy(c) + ky;
        double sx = 0.0, sy = 0.0;
        if (cx < 0) { if (!g.periodic_x()) continue; cx += g.nx(); sx = -g.lx(); }
        if (cx >= g.nx()) { if (!g.periodic_x()) continue; cx -= g.nx(); sx = g.lx(); }
        if (cy < 0) { if (!g.periodic_y()) continue; cy += g.ny(); sy = -g.ly(); }
        if (cy >= g.ny()) { if (!g.periodic_y()) continue; cy -= g.ny(); sy = g.ly(); }
        const int cc = g.index(cx, cy);
        for (int k = 0; k < g.count(cc); ++k) {
          const int j = g.member(cc, k);
          if (j <= i) continue;
          const Vec2 pj = s_.position_now(j) + Vec2{sx, sy};
          gap = std::min(gap, (pi - pj).norm() - s_.body[i].r - s_.body[j].r);
        }
      }
  }
  return gap;
}

std::vector<Simulation::MemoryPart> Simulation::memory_parts() const {
  // Agents and frozen disks read the bodies at their events, and the slot states, as do
  // timers' actions, which add, remove and touch disks (see simulation.hpp).
  const bool bodies_hot = !s_.plain_disks() || !s_.agents.empty() || s_.frozen_count() > 0;
  const bool slots_hot = !s_.agents.empty() || !s_.timers.empty() || s_.frozen_count() > 0;
  return {{"disk records", s_.disk.capacity() * sizeof(Disk), true},
          {"bodies", s_.body.capacity() * sizeof(DiskBody), bodies_hot},
          {"event records", s_.event.capacity() * sizeof(NextEvent), true},
          {"agent event times", s_.agent_time.capacity() * sizeof(double), !s_.agents.empty()},
          {"counters", s_.counter.capacity() * sizeof(std::uint32_t), true},
          {"slot states", s_.slot.capacity() * sizeof(SlotState), slots_hot},
          {"cell map", s_.grid.memory_bytes(), true},
          {"calendar", loop_->calendar_bytes(), true},
          {"ids", s_.tag.capacity() * sizeof(std::int64_t), false},
          {"TC times", s_.last_collision.capacity() * sizeof(double), s_.tc_on()},
          {"lanes' restart copy and stamps", loop_->lane_bytes(), false}};
}

std::size_t Simulation::memory_bytes() const {
  std::size_t b = 0;
  for (const MemoryPart& p : memory_parts()) b += p.bytes;
  return b;
}

}  // namespace grainflow::ed
