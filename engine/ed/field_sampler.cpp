#include "engine/ed/field_sampler.hpp"

#include <cmath>

#include <fmt/format.h>

#include "engine/core/error.hpp"
#include "engine/ed/system_state.hpp"

namespace grainflow::ed {

namespace {
core::BinningOptions options(const SamplerConfig& c) {
  core::BinningOptions o;
  o.grid = c.grid;
  return o;
}
}  // namespace

FieldSampler::FieldSampler(const SamplerConfig& cfg, double t_start)
    : cfg_(cfg), acc_(options(cfg)), t_start_(t_start), t_begin_(t_start) {
  if (!(cfg.interval > 0.0) || !std::isfinite(cfg.interval))
    throw Error(fmt::format("ed sampler: interval = {} is invalid; it must be a positive time", cfg.interval));
  if (!(cfg.exposure >= cfg.interval) || !std::isfinite(cfg.exposure))
    throw Error(fmt::format("ed sampler: exposure = {} is invalid; it must be at least the sampling "
                            "interval {}", cfg.exposure, cfg.interval));
  per_exposure_ = static_cast<int>(std::lround(cfg.exposure / cfg.interval));
}

double FieldSampler::event_time(const SystemState&) const {
  // Computed from the start time, not accumulated, so sample times do not drift.
  return t_start_ + static_cast<double>(k_ + 1) * cfg_.interval;
}

void FieldSampler::action(SystemState& s) {
  ++k_;
  const CellGrid& g = s.grid;
  acc_.begin_frame(2, true, true);
  for (int i = 0; i < s.size(); ++i) {
    // Empty slots, and frozen disks beyond the outlet filter: those are the boundary
    // (infinitely heavy, no thermal motion, §3.3), not the gas, as the obstacle is.
    if (!s.present(i) || s.frozen(i)) continue;
    Vec2 p = s.position_now(i);
    // Cells keep disks inside the box up to round-off; wrap periodic coordinates exactly.
    if (g.periodic_x()) p.x() -= g.lx() * std::floor(p.x() / g.lx());
    if (g.periodic_y()) p.y() -= g.ly() * std::floor(p.y() / g.ly());
    const Disk& d = s.disk[i];
    acc_.deposit({p.x(), p.y(), 0.0}, {d.vx, d.vy, 0.0}, d.r, s.disk[i].m);
  }
  acc_.end_frame();
  if (k_ % per_exposure_ == 0) {
    ExposureFields f;
    f.t_begin = t_begin_;
    f.t_end = s.now();
    f.samples = acc_.frames();
    f.fields.density = acc_.density();
    f.fields.fraction = acc_.fraction();
    f.fields.mean_velocity = acc_.mean_velocity();
    f.fields.temperature = acc_.temperature();
    f.fields.mean_speed = acc_.mean_speed();
    frames_.push_back(std::move(f));
    acc_.reset();
    t_begin_ = s.now();
  }
}

std::vector<ExposureFields> FieldSampler::take_frames() {
  std::vector<ExposureFields> out;
  out.swap(frames_);
  return out;
}

}  // namespace grainflow::ed
