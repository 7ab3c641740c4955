#include "engine/ed/thermostat.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include <fmt/format.h>

#include "engine/core/error.hpp"
#include "engine/ed/system_state.hpp"
#include "engine/io/archive.hpp"

namespace grainflow::ed {

std::string_view thermostat_kind_name(ThermostatKind k) {
  switch (k) {
    case ThermostatKind::single: return "single";
    case ThermostatKind::dual: return "dual";
    case ThermostatKind::global: return "global";
  }
  return "?";
}

namespace {

void require_positive(std::string_view key, double v, std::string_view what) {
  if (!(v > 0.0) || !std::isfinite(v))
    throw Error(fmt::format("ed thermostat: {} = {} is invalid; it must be a positive {}", key, v, what));
}

// The mean velocity of the mobile disks from the engine's books (0 without disks).
Vec2 global_mean(const SystemState& s) {
  const double m = s.total_mass();
  return m > 0.0 ? Vec2(s.momentum() / m) : Vec2(Vec2::Zero());
}

// Disk i's centre now, periodic coordinates wrapped into the box exactly (as the field
// sampler does: cells keep disks inside the box only up to round-off).
Vec2 wrapped_position(const SystemState& s, int i) {
  const CellGrid& g = s.grid;
  Vec2 p = s.position_now(i);
  if (g.periodic_x()) p.x() -= g.lx() * std::floor(p.x() / g.lx());
  if (g.periodic_y()) p.y() -= g.ly() * std::floor(p.y() / g.ly());
  return p;
}

}  // namespace

Thermostat::Thermostat(const ThermostatConfig& cfg, const SystemState& state)
    : cfg_(cfg), t_start_(state.now()), rng_(cfg.seed) {
  require_positive("T", cfg.kT, "temperature");
  require_positive("tau", cfg.tau, "time");
  if (cfg.kind == ThermostatKind::single) {
    require_positive("tau_v", cfg.tau_v, "time");
    require_positive("sample_interval", cfg.sample_interval, "time");
    const core::GridGeometry& g = cfg.grid;
    if (g.nx < 1 || g.ny < 1 || !(g.hi.x() > g.lo.x()) || !(g.hi.y() > g.lo.y()))
      throw Error(fmt::format("ed thermostat: bins of {} x {} over [{}, {}] x [{}, {}] are invalid; allowed: at least "
                              "one bin over a rectangle of positive area",
                              g.nx, g.ny, g.lo.x(), g.hi.x(), g.lo.y(), g.hi.y()));
    decay_ = std::exp(-cfg.sample_interval / cfg.tau_v);
    mass_.assign(g.size(), 0.0);
    mom_.assign(2 * g.size(), 0.0);
  }
  draw_next(state);
}

double Thermostat::sample_time() const {
  if (cfg_.kind != ThermostatKind::single) return kNever;
  // From the start time, not accumulated, so sample times do not drift.
  return t_start_ + static_cast<double>(k_ + 1) * cfg_.sample_interval;
}

double Thermostat::event_time(const SystemState&) const {
  return active_ ? std::min(sample_time(), next_) : sample_time();
}

void Thermostat::set_active(bool on, SystemState& s) {
  if (on && !active_) draw_next(s);
  active_ = on;
  s.reschedule(this);
}

void Thermostat::set_temperature(double kT) {
  require_positive("T", kT, "temperature");
  cfg_.kT = kT;
}

void Thermostat::action(SystemState& s) {
  const double t = s.now();
  // A sample due at the same time as an event is taken first.
  if (sample_time() <= t) sample(s);
  if (active_ && next_ <= t) {
    kick(s);
    draw_next(s);
  }
}

void Thermostat::draw_next(const SystemState& s) {
  // Each disk once per τ on average: N/τ events (single, global), N/(2τ) pair events (dual).
  const double per_disk = cfg_.kind == ThermostatKind::dual ? 2.0 * cfg_.tau : cfg_.tau;
  const int n = std::max(1, s.mobile_count());
  next_ = s.now() - std::log(rng_.uniform_pos()) * per_disk / n;
}

bool Thermostat::bin_mean(std::size_t b, Vec2& v) const {
  if (b >= mass_.size() || !(mass_[b] > 0.0)) return false;
  v = Vec2(mom_[2 * b] / mass_[b], mom_[2 * b + 1] / mass_[b]);
  return true;
}

void Thermostat::sample(SystemState& s) {
  ++k_;
  const core::GridGeometry& g = cfg_.grid;
  frame_mass_.assign(g.size(), 0.0);
  frame_mom_.assign(2 * g.size(), 0.0);
  for (int i = 0; i < s.size(); ++i) {
    if (!s.present(i) || s.frozen(i)) continue;  // frozen disks are the boundary, not the gas
    int ix = 0, iy = 0;
    if (!g.bin_of(wrapped_position(s, i), ix, iy)) continue;
    const std::size_t b = g.index(ix, iy);
    const DiskNow d = s.disk_now(i);
    frame_mass_[b] += d.m;
    frame_mom_[2 * b] += d.m * d.vx;
    frame_mom_[2 * b + 1] += d.m * d.vy;
  }
  const double f = decay_, w = 1.0 - decay_;
  for (std::size_t b = 0; b < mass_.size(); ++b) mass_[b] = f * mass_[b] + w * frame_mass_[b];
  for (std::size_t k = 0; k < mom_.size(); ++k) mom_[k] = f * mom_[k] + w * frame_mom_[k];
}

int Thermostat::random_mobile(const SystemState& s) {
  if (s.mobile_count() == 0) return -1;
  // Uniform over the mobile disks: uniform slots, absent and frozen ones rejected.
  for (;;) {
    const int i = static_cast<int>(rng_.below(static_cast<std::uint64_t>(s.size())));
    if (s.present(i) && !s.frozen(i)) return i;
  }
}

int Thermostat::random_partner(const SystemState& s, int i) {
  const CellGrid& g = s.grid;
  const int c = g.cell(i);
  partners_.clear();
  g.for_neighbour_cells(c, [&](int cc) {
    for (int k = 0, n = g.count(cc); k < n; ++k) {
      const int j = g.member(cc, k);
      if (j != i && !s.frozen(j)) partners_.push_back(j);
    }
  });
  if (partners_.empty()) return -1;
  return partners_[static_cast<std::size_t>(rng_.below(partners_.size()))];
}

void Thermostat::kick(SystemState& s) {
  const int i = random_mobile(s);
  if (i < 0) return;
  ThermostatEvent ev;
  ev.t = s.now();
  ev.i = i;
  ev.mi = s.body[i].m;
  ev.vi_before = Vec2(s.disk[i].vx, s.disk[i].vy);
  const double kT = cfg_.kT;
  if (cfg_.kind == ThermostatKind::dual) {
    const int j = random_partner(s, i);
    if (j < 0) {
      ++unpaired_;
      return;
    }
    ev.j = j;
    ev.mj = s.body[j].m;
    ev.vj_before = Vec2(s.disk[j].vx, s.disk[j].vy);
    const double mi = ev.mi, mj = ev.mj, M = mi + mj, mu = mi * mj / M;
    const Vec2 c = (mi * ev.vi_before + mj * ev.vj_before) / M;
    const double sd = std::sqrt(kT / mu);
    const double gx = sd * rng_.normal();
    const double gy = sd * rng_.normal();
    const Vec2 g(gx, gy);
    ev.mean = c;
    ev.vi_after = c + (mj / M) * g;
    ev.vj_after = c - (mi / M) * g;
    ev.fluctuation = ev.vi_after - ev.vj_after;
    energy_ += 0.5 * mi * (ev.vi_after.squaredNorm() - ev.vi_before.squaredNorm()) +
               0.5 * mj * (ev.vj_after.squaredNorm() - ev.vj_before.squaredNorm());
    s.set_velocity(i, ev.vi_after.x(), ev.vi_after.y());
    s.set_velocity(j, ev.vj_after.x(), ev.vj_after.y());
  } else {
    Vec2 mean = Vec2::Zero();
    if (cfg_.kind == ThermostatKind::single) {
      int ix = 0, iy = 0;
      if (cfg_.grid.bin_of(wrapped_position(s, i), ix, iy)) ev.local = bin_mean(cfg_.grid.index(ix, iy), mean);
    }
    if (!ev.local) mean = global_mean(s);
    const double sd = std::sqrt(kT / ev.mi);
    const double xi_x = sd * rng_.normal();
    const double xi_y = sd * rng_.normal();
    ev.mean = mean;
    ev.fluctuation = Vec2(xi_x, xi_y);
    ev.vi_after = mean + ev.fluctuation;
    energy_ += 0.5 * ev.mi * (ev.vi_after.squaredNorm() - ev.vi_before.squaredNorm());
    s.set_velocity(i, ev.vi_after.x(), ev.vi_after.y());
  }
  ++events_;
  if (on_event) on_event(ev);
}

void Thermostat::save(io::ArchiveWriter& w) const {
  w.tag("thermostat");
  w.string(thermostat_kind_name(cfg_.kind));
  w.pod(static_cast<std::int32_t>(cfg_.grid.nx));
  w.pod(static_cast<std::int32_t>(cfg_.grid.ny));
  w.flag(!mass_.empty());  // holds averaged bins (single)
  w.pod(t_start_);
  w.pod(k_);
  w.pod(next_);
  w.rng(rng_);
  w.array(mass_);
  w.array(mom_);
  w.pod(events_);
  w.pod(unpaired_);
  w.pod(energy_);
  w.flag(active_);
  w.pod(cfg_.kT);
}

void Thermostat::load(io::ArchiveReader& r) {
  r.tag("thermostat");
  const std::string kind = r.string();
  const auto nx = r.get<std::int32_t>(), ny = r.get<std::int32_t>();
  const bool binned = r.flag("the thermostat's bins flag");
  if (kind != thermostat_kind_name(cfg_.kind) || binned != !mass_.empty() ||
      (binned && (nx != cfg_.grid.nx || ny != cfg_.grid.ny)))
    r.mismatch(fmt::format("the thermostat is '{}' on {} x {} bins in the archive, '{}' on {} x {} here", kind, nx, ny,
                           thermostat_kind_name(cfg_.kind), cfg_.grid.nx, cfg_.grid.ny));
  // Read into locals first: a failure leaves nothing half-loaded (the simulation puts the
  // agents back anyway).
  double t_start = 0.0, next = 0.0, energy = 0.0;
  std::int64_t k = 0;
  std::uint64_t events = 0, unpaired = 0;
  core::Rng rng;
  std::vector<double> mass, mom;
  r.pod(t_start);
  r.pod(k);
  r.pod(next);
  r.rng(rng);
  r.array_of(mass, mass_.size(), "the thermostat's bin masses");
  r.array_of(mom, mom_.size(), "the thermostat's bin momenta");
  r.pod(events);
  r.pod(unpaired);
  r.pod(energy);
  const bool active = r.flag("the thermostat's on/off flag");
  const double kT = r.get<double>();
  if (!(kT > 0.0)) r.corrupt(fmt::format("the thermostat's temperature is {}", kT));
  if (k < 0) r.corrupt(fmt::format("the thermostat took {} samples", k));
  t_start_ = t_start;
  k_ = k;
  next_ = next;
  rng_ = rng;
  mass_ = std::move(mass);
  mom_ = std::move(mom);
  events_ = events;
  unpaired_ = unpaired;
  energy_ = energy;
  active_ = active;
  cfg_.kT = kT;
}

}  // namespace grainflow::ed
