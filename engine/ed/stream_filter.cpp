#include "engine/ed/stream_filter.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "engine/core/error.hpp"
#include "engine/ed/checkpoint.hpp"
#include "engine/ed/system_state.hpp"

namespace grainflow::ed {

StreamFilter::StreamFilter(const FilterConfig& cfg)
    : cfg_(cfg), xf_(cfg.lx - cfg.distance), flux_(cfg.U, cfg.kT, cfg.mass), rng_(cfg.seed) {
  if (!(cfg.distance > 0.0 && cfg.distance < cfg.lx))
    throw Error(fmt::format("ed filter: distance = {} is invalid; allowed: 0 < distance < Lx = {}", cfg.distance,
                            cfg.lx));
  if (cfg.local_kT && !(cfg.window >= 1.0 && std::isfinite(cfg.window)))
    throw Error(fmt::format("ed filter: window = {} is invalid; allowed: a finite number of disks >= 1", cfg.window));
  if (cfg.local_kT) arrivals_ = ArrivalTemperature(cfg.kT, cfg.mass, cfg.window);
}

void StreamFilter::cells(const CellGrid& g, std::vector<int>& out) const {
  // Disks that can reach x_f before leaving their cell, and every cell beyond (frozen
  // disks travel to Lx there).
  for (int ix = 0; ix < g.nx(); ++ix)
    if ((ix + 1) * g.width() >= xf_)
      for (int iy = 0; iy < g.ny(); ++iy) out.push_back(g.index(ix, iy));
}

double StreamFilter::event_time(const SystemState& s, int i, const DiskNow& d) const {
  if (!(d.vx > 0.0)) return kNever;
  if (s.frozen(i)) return cfg_.delete_instead_of_freeze ? kNever : std::max(0.0, cfg_.lx - d.x) / d.vx;
  return std::max(0.0, xf_ - d.x) / d.vx;
}

void StreamFilter::action(SystemState& s, int i) {
  if (s.frozen(i)) {  // reached the real boundary
    s.remove_disk(i);
    return;
  }
  if (cfg_.local_kT) {
    arrivals_.observe(s.disk[i].vy);
    const double kT = arrivals_.kT();
    // A floor far below any temperature the TC model lets a stream reach keeps the flux finite.
    if (kT > 1e-12 * cfg_.kT && std::abs(std::log(kT / flux_.kT())) > 0.02) flux_ = StreamFlux(cfg_.U, kT, cfg_.mass);
  }
  if (rng_.uniform() < flux_.turn_back_probability()) {
    const Vec2 v = flux_.sample_backward(rng_);
    ++turned_;
    s.set_velocity(i, v.x(), v.y());
  } else if (cfg_.delete_instead_of_freeze) {
    s.remove_disk(i);
  } else {
    ++frozen_;
    s.freeze(i, cfg_.U, 0.0);
  }
}

// Its random stream, counters and (local_kT) the arrivals' running means and the
// temperature of the flux in use; the plane is configuration.
void StreamFilter::save(io::ArchiveWriter& w) const {
  w.rng(rng_);
  w.pod(turned_);
  w.pod(frozen_);
  if (cfg_.local_kT) {
    w.pod(arrivals_.mean_vy());
    w.pod(arrivals_.mean_vy2());
    w.pod(flux_.kT());
  }
}

void StreamFilter::load(io::ArchiveReader& r) {
  r.rng(rng_);
  r.pod(turned_);
  r.pod(frozen_);
  if (cfg_.local_kT) {
    double mvy = 0.0, mvy2 = 0.0, kT = 0.0;
    r.pod(mvy);
    r.pod(mvy2);
    r.pod(kT);
    arrivals_.restore(mvy, mvy2);
    flux_ = StreamFlux(cfg_.U, kT, cfg_.mass);
  }
}

}  // namespace grainflow::ed
