#include "engine/ed/dispenser.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "engine/core/error.hpp"
#include "engine/ed/checkpoint.hpp"
#include "engine/ed/system_state.hpp"

namespace grainflow::ed {

DispenserPiston::DispenserPiston(const DispenserConfig& cfg, double t0, double ly, bool periodic_y)
    : cfg_(cfg), ly_(ly), periodic_y_(periodic_y), strip_(2.0 * cfg.radius), t_cycle_(t0), rng_(cfg.seed) {
  auto bad = [](std::string_view key, double v, std::string_view allowed) {
    throw Error(fmt::format("ed dispenser: {} = {} is invalid; allowed: {}", key, v, allowed));
  };
  if (!(cfg.U >= 0.0) || !std::isfinite(cfg.U)) bad("U", cfg.U, "U >= 0 (the stream runs along +x)");
  if (!(cfg.kT > 0.0) || !std::isfinite(cfg.kT)) bad("kT", cfg.kT, "kT > 0");
  if (!(cfg.radius > 0.0) || !(cfg.mass > 0.0)) bad("radius", cfg.radius, "positive radius and mass");
  // One row of disks at least a diameter apart along y: η·2R·L/(πR²) centres on a line of
  // length L need η < π/4.
  if (!(cfg.area_fraction > 0.0 && cfg.area_fraction < std::numbers::pi / 4.0))
    bad("area_fraction", cfg.area_fraction, "0 < η < π/4 ≈ 0.785 (a monolayer must fit in the strip)");
  if (cfg.local_kT && !(cfg.window >= 1.0 && std::isfinite(cfg.window))) bad("window", cfg.window, "a number of disks >= 1");
  if (cfg.local_kT) arrivals_ = ArrivalTemperature(cfg.kT, cfg.mass, cfg.window);
  t_recharge_ = cfg.U > 0.0 ? t0 + strip_ / cfg.U : kNever;
}

void DispenserPiston::cells(const CellGrid& g, std::vector<int>& out) const {
  // A disk touching the piston (X ∈ [0, strip]) has its centre in [R, strip + R].
  const double reach = strip_ + cfg_.radius;
  for (int ix = 0; ix < g.nx() && ix * g.width() <= reach; ++ix)
    for (int iy = 0; iy < g.ny(); ++iy) out.push_back(g.index(ix, iy));
}

double DispenserPiston::event_time(const SystemState& s, int i, const DiskNow& d) const {
  if (s.frozen(i)) return kNever;
  const double closing = cfg_.U - d.vx;  // piston overtakes the disk's left edge
  if (!(closing > 0.0)) return kNever;
  const double dt = std::max(0.0, d.x - d.r - position(d.t)) / closing;
  // The piston vanishes at the recharge: later contacts belong to the next cycle.
  return d.t + dt <= t_recharge_ ? dt : kNever;
}

void DispenserPiston::action(SystemState& s, int i) {
  const DiskNow d = s.disk_now(i);
  if (cfg_.local_kT) arrivals_.observe(d.vy);
  double vx = 2.0 * cfg_.U - d.vx, vy = d.vy;  // specular in the piston frame
  if (cfg_.piston == PistonKind::thermal) {
    // Diffuse re-emission from a wall at the stream temperature moving at U [TTKB98]: the
    // flux-weighted normal speed has the Rayleigh density, the tangential one is Gaussian.
    const double s2 = kT() / s.body[i].m;
    vx = cfg_.U + std::sqrt(-2.0 * s2 * std::log(rng_.uniform_pos()));
    vy = std::sqrt(s2) * rng_.normal();
  }
  impulse_x_ += s.body[i].m * (vx - d.vx);
  ++hits_;
  s.set_velocity(i, vx, vy);
}

void DispenserPiston::recharge(SystemState& s) {
  ++cycles_;
  // How many disks the swept strip held in the stream; the fraction is carried over.
  owed_ += cfg_.area_fraction * strip_ * ly_ / (std::numbers::pi * cfg_.radius * cfg_.radius);
  const double d = 2.0 * cfg_.radius;
  // Line of centres: periodic y — a circle of length Ly; walls — [R, Ly − R].
  const double line = periodic_y_ ? ly_ : ly_ - d;
  const int fit = periodic_y_ ? static_cast<int>(std::floor(line / d)) : static_cast<int>(std::floor(line / d)) + 1;
  const int k = std::clamp(static_cast<int>(std::floor(owed_)), 0, std::max(0, fit));
  owed_ -= k;
  if (k > 0) {
    // Hard rods in equilibrium on the line: the free length is split by uniform spacings
    // (normalised exponentials), k gaps on a circle or k + 1 between two walls.
    const int ngaps = periodic_y_ ? k : k + 1;
    const double free = line - (periodic_y_ ? k : k - 1) * d;
    gaps_.resize(ngaps);
    double sum = 0.0;
    for (double& g : gaps_) sum += (g = -std::log(rng_.uniform_pos()));
    double y = periodic_y_ ? rng_.uniform() * ly_ : cfg_.radius;
    const double kT = this->kT();
    const double sd = std::sqrt(kT / cfg_.mass);
    const double inertia = cfg_.q * cfg_.mass * cfg_.radius * cfg_.radius;
    for (int n = 0; n < k; ++n) {
      y += gaps_[n] / sum * free;
      if (periodic_y_ && y >= ly_) y -= ly_;
      DiskInit in;
      in.r = {0.5 * strip_, std::clamp(y, 0.0, std::nextafter(ly_, 0.0))};
      in.v = {cfg_.U + sd * rng_.normal(), sd * rng_.normal()};
      in.omega = cfg_.rotation ? std::sqrt(kT / inertia) * rng_.normal() : 0.0;
      in.radius = cfg_.radius;
      in.mass = cfg_.mass;
      s.add_disk(in);
      y += d;
    }
  }
  // The piston jumps back: disks of the strip had predictions against its old place.
  t_cycle_ = s.now();
  t_recharge_ = s.now() + strip_ / cfg_.U;
  if (cells_.empty()) cells(s.grid, cells_);
  for (int c : cells_) {
    for (int n = 0, cnt = s.grid.count(c); n < cnt; ++n) s.repredict(s.grid.member(c, n));
  }
}

// The cycle (start, recharge time), the fractional disk owed, the random stream and the
// counters. The cell list and gap scratch are rebuilt (the same cells) or overwritten.
void DispenserPiston::save(io::ArchiveWriter& w) const {
  w.pod(t_cycle_);
  w.pod(t_recharge_);
  w.pod(owed_);
  w.rng(rng_);
  w.pod(hits_);
  w.pod(cycles_);
  w.pod(impulse_x_);
  if (cfg_.local_kT) {
    w.pod(arrivals_.mean_vy());
    w.pod(arrivals_.mean_vy2());
  }
}

void DispenserPiston::load(io::ArchiveReader& r) {
  r.pod(t_cycle_);
  r.pod(t_recharge_);
  r.pod(owed_);
  r.rng(rng_);
  r.pod(hits_);
  r.pod(cycles_);
  r.pod(impulse_x_);
  if (cfg_.local_kT) {
    double mvy = 0.0, mvy2 = 0.0;
    r.pod(mvy);
    r.pod(mvy2);
    arrivals_.restore(mvy, mvy2);
  }
}

}  // namespace grainflow::ed
