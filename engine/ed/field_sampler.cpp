#include "engine/ed/field_sampler.hpp"

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "engine/core/error.hpp"
#include "engine/ed/checkpoint.hpp"
#include "engine/ed/system_state.hpp"
#include "engine/io/archive.hpp"

namespace grainflow::ed {

namespace {
core::BinningOptions options(const SamplerConfig& c) {
  core::BinningOptions o;
  o.grid = c.grid;
  return o;
}

// ---- completed frames ---------------------------------------------------------------------
void write_grid(io::ArchiveWriter& w, const core::GridGeometry& g) {
  w.pod(static_cast<std::int32_t>(g.nx));
  w.pod(static_cast<std::int32_t>(g.ny));
  checkpoint::write_vec2(w, g.lo);
  checkpoint::write_vec2(w, g.hi);
}
core::GridGeometry read_grid(io::ArchiveReader& r) {
  core::GridGeometry g;
  g.nx = r.get<std::int32_t>();
  g.ny = r.get<std::int32_t>();
  g.lo = checkpoint::read_vec2(r);
  g.hi = checkpoint::read_vec2(r);
  if (g.nx < 0 || g.ny < 0) r.corrupt(fmt::format("a sampled field has {} x {} bins", g.nx, g.ny));
  return g;
}

void write_field(io::ArchiveWriter& w, const core::ScalarField& f) {
  write_grid(w, f.grid);
  w.array(f.values);
  w.array(f.mask);
}
void write_field(io::ArchiveWriter& w, const core::VectorField& f) {
  write_grid(w, f.grid);
  std::vector<double> flat;
  flat.reserve(2 * f.values.size());
  for (const Vec2& v : f.values) flat.insert(flat.end(), {v.x(), v.y()});
  w.array(flat);
  w.array(f.mask);
}
void read_field(io::ArchiveReader& r, core::ScalarField& f) {
  f.grid = read_grid(r);
  r.array_of(f.values, f.grid.size(), "a sampled field's values");
  r.array_of(f.mask, f.grid.size(), "a sampled field's mask");
}
void read_field(io::ArchiveReader& r, core::VectorField& f) {
  f.grid = read_grid(r);
  std::vector<double> flat;
  r.array_of(flat, 2 * f.grid.size(), "a sampled field's vectors");
  f.values.resize(f.grid.size());
  for (std::size_t b = 0; b < f.values.size(); ++b) f.values[b] = Vec2(flat[2 * b], flat[2 * b + 1]);
  r.array_of(f.mask, f.grid.size(), "a sampled field's mask");
}
template <class F>
void write_optional(io::ArchiveWriter& w, const std::optional<F>& f) {
  w.flag(f.has_value());
  if (f) write_field(w, *f);
}
template <class F>
void read_optional(io::ArchiveReader& r, std::optional<F>& f) {
  f.reset();
  if (r.flag("a sampled field's presence flag")) read_field(r, f.emplace());
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
    const DiskNow d = s.disk_now(i);
    acc_.deposit({p.x(), p.y(), 0.0}, {d.vx, d.vy, 0.0}, d.r, s.body[i].m);
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
    f.fields.counts = acc_.counts();
    frames_.push_back(std::move(f));
    acc_.reset();
    t_begin_ = s.now();
  }
}

void FieldSampler::save(io::ArchiveWriter& w) const {
  w.pod(static_cast<std::int32_t>(per_exposure_));
  w.pod(static_cast<std::int32_t>(cfg_.grid.nx));
  w.pod(static_cast<std::int32_t>(cfg_.grid.ny));
  w.pod(t_start_);
  w.pod(static_cast<std::int64_t>(k_));
  w.pod(t_begin_);
  io::save(w, acc_);
  w.pod(static_cast<std::uint64_t>(frames_.size()));
  for (const ExposureFields& f : frames_) {
    w.pod(f.t_begin);
    w.pod(f.t_end);
    w.pod(static_cast<std::int32_t>(f.samples));
    write_field(w, f.fields.density);
    write_optional(w, f.fields.fraction);
    write_optional(w, f.fields.mean_velocity);
    write_optional(w, f.fields.temperature);
    write_optional(w, f.fields.mean_speed);
    w.array(f.fields.counts);
  }
}

void FieldSampler::load(io::ArchiveReader& r) {
  const auto per = r.get<std::int32_t>();
  const auto nx = r.get<std::int32_t>(), ny = r.get<std::int32_t>();
  if (per != per_exposure_ || nx != cfg_.grid.nx || ny != cfg_.grid.ny)
    r.mismatch(fmt::format("the sampler takes {} samples per exposure on {} x {} bins in the archive, {} on {} x {} "
                           "here", per, nx, ny, per_exposure_, cfg_.grid.nx, cfg_.grid.ny));
  r.pod(t_start_);
  k_ = static_cast<long long>(r.get<std::int64_t>());
  r.pod(t_begin_);
  io::load(r, acc_);
  const auto n = r.get<std::uint64_t>();
  // A frame costs more than 64 bytes: a corrupt count cannot reserve much.
  if (n > r.left() / 64) r.corrupt(fmt::format("{} sampled frames in {} bytes", n, r.left()));
  frames_.assign(static_cast<std::size_t>(n), ExposureFields{});
  for (ExposureFields& f : frames_) {
    r.pod(f.t_begin);
    r.pod(f.t_end);
    f.samples = r.get<std::int32_t>();
    read_field(r, f.fields.density);
    read_optional(r, f.fields.fraction);
    read_optional(r, f.fields.mean_velocity);
    read_optional(r, f.fields.temperature);
    read_optional(r, f.fields.mean_speed);
    r.array_of(f.fields.counts, cfg_.grid.size(), "the sampled frame's bin counts");
  }
}

std::vector<ExposureFields> FieldSampler::take_frames() {
  std::vector<ExposureFields> out;
  out.swap(frames_);
  return out;
}

}  // namespace grainflow::ed
