#include "engine/core/binning.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "engine/core/error.hpp"

namespace grainflow::core {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

BinAccumulator::BinAccumulator(const BinningOptions& options) : opt_(options) {
  const auto& g = opt_.grid;
  if (g.nx < 1 || g.ny < 1)
    throw Error("binning grid must have at least 1 × 1 bins, got " + std::to_string(g.nx) + " × " + std::to_string(g.ny));
  if (!(g.hi.x() > g.lo.x()) || !(g.hi.y() > g.lo.y()))
    throw Error("binning grid: hi must exceed lo on both axes");
  if (opt_.slab_lo.has_value() != opt_.slab_hi.has_value())
    throw Error("binning slab: give both slab_lo and slab_hi, or neither");
  if (opt_.slab_lo && !(*opt_.slab_hi > *opt_.slab_lo)) throw Error("binning slab: slab_hi must exceed slab_lo");
  switch (opt_.plane) {
    case BinPlane::xy: axis_u_ = 0, axis_v_ = 1, axis_w_ = 2; break;
    case BinPlane::xz: axis_u_ = 0, axis_v_ = 2, axis_w_ = 1; break;
    case BinPlane::yz: axis_u_ = 1, axis_v_ = 2, axis_w_ = 0; break;
  }
  reset();
}

void BinAccumulator::reset() {
  const std::size_t n = opt_.grid.size();
  dim_ = 0;
  frames_ = 0;
  all_vel_ = all_rad_ = all_slab_ = true;
  slab_sum_ = 0.0;
  outside_ = 0;
  count_.assign(n, 0);
  mass_.assign(n, 0.0);
  vol_.assign(n, 0.0);
  speed_.assign(n, 0.0);
  msq_.assign(n, 0.0);
  mom_.assign(n, Vec3::Zero());
}

void BinAccumulator::check_dim(int dim) {
  if (dim != 2 && dim != 3) throw Error("binning: dimension must be 2 or 3, got " + std::to_string(dim));
  if (dim == 2 && opt_.plane != BinPlane::xy) throw Error("binning: a 2D system can only be binned in the xy plane");
  if (dim_ != 0 && dim != dim_)
    throw Error("binning: a " + std::to_string(dim) + "D frame added to an average of " + std::to_string(dim_) + "D frames");
  dim_ = dim;
}

void BinAccumulator::begin_frame(int dim, bool with_velocity, bool with_radius, double slab_thickness) {
  check_dim(dim);
  frame_vel_ = with_velocity;
  frame_rad_ = with_radius;
  all_vel_ = all_vel_ && with_velocity;
  all_rad_ = all_rad_ && with_radius;
  if (dim == 3) {
    if (opt_.slab_lo) slab_thickness = *opt_.slab_hi - *opt_.slab_lo;
    if (slab_thickness > 0.0) slab_sum_ += slab_thickness;
    else all_slab_ = false;
  }
}

void BinAccumulator::deposit(const Vec3& p, const Vec3& v, double radius, double mass) {
  if (dim_ == 3 && opt_.slab_lo) {
    const double w = p[axis_w_];
    if (!(w >= *opt_.slab_lo && w < *opt_.slab_hi)) return void(++outside_);
  }
  int ix, iy;
  if (!opt_.grid.bin_of(Vec2(p[axis_u_], p[axis_v_]), ix, iy)) return void(++outside_);
  const std::size_t b = opt_.grid.index(ix, iy);
  ++count_[b];
  mass_[b] += mass;
  if (frame_rad_)
    vol_[b] += dim_ == 2 ? std::numbers::pi * radius * radius : (4.0 / 3.0) * std::numbers::pi * radius * radius * radius;
  if (frame_vel_) {
    mom_[b] += mass * v;
    msq_[b] += mass * v.squaredNorm();
    speed_[b] += v.norm();
  }
}

void BinAccumulator::end_frame() {
  ++frames_;
}

void BinAccumulator::add(const ParticleFrame& f) {
  f.check_consistent("binning");
  const std::vector<double>* mass = nullptr;
  for (const auto& [name, values] : f.extra)
    if (name == "mass") mass = &values;
  double slab = 0.0;
  if (f.dim == 3 && f.has_box) slab = f.box_hi[axis_w_] - f.box_lo[axis_w_];
  begin_frame(f.dim, f.has_velocity(), true, slab);
  for (std::size_t i = 0; i < f.size(); ++i) {
    Vec3 p = f.position[i];
    Vec3 v = f.has_velocity() ? f.velocity[i] : Vec3::Zero();
    if (f.dim == 2) p.z() = 0.0, v.z() = 0.0;
    deposit(p, v, f.radius[i], mass ? (*mass)[i] : 1.0);
  }
  end_frame();
}

void BinAccumulator::add(std::span<const Vec2> position, std::span<const Vec2> velocity, std::span<const double> radius,
                         std::span<const double> mass) {
  const std::size_t n = position.size();
  if ((!velocity.empty() && velocity.size() != n) || (!radius.empty() && radius.size() != n) ||
      (!mass.empty() && mass.size() != n))
    throw Error("binning: position, velocity, radius and mass arrays differ in length");
  begin_frame(2, !velocity.empty(), !radius.empty());
  for (std::size_t i = 0; i < n; ++i)
    deposit(Vec3(position[i].x(), position[i].y(), 0.0),
            velocity.empty() ? Vec3::Zero() : Vec3(velocity[i].x(), velocity[i].y(), 0.0),
            radius.empty() ? 0.0 : radius[i], mass.empty() ? 1.0 : mass[i]);
  end_frame();
}

void BinAccumulator::add(std::span<const Vec3> position, std::span<const Vec3> velocity, std::span<const double> radius,
                         std::span<const double> mass, double slab_thickness) {
  const std::size_t n = position.size();
  if ((!velocity.empty() && velocity.size() != n) || (!radius.empty() && radius.size() != n) ||
      (!mass.empty() && mass.size() != n))
    throw Error("binning: position, velocity, radius and mass arrays differ in length");
  begin_frame(3, !velocity.empty(), !radius.empty(), slab_thickness);
  for (std::size_t i = 0; i < n; ++i)
    deposit(position[i], velocity.empty() ? Vec3::Zero() : velocity[i], radius.empty() ? 0.0 : radius[i],
            mass.empty() ? 1.0 : mass[i]);
  end_frame();
}

ScalarField BinAccumulator::density() const {
  ScalarField out(opt_.grid, 0.0);
  if (frames_ == 0) return out;
  const double norm = 1.0 / (frames_ * opt_.grid.dx() * opt_.grid.dy());
  for (std::size_t b = 0; b < count_.size(); ++b) out.values[b] = static_cast<double>(count_[b]) * norm;
  return out;
}

ScalarField BinAccumulator::fraction() const {
  if (!all_rad_) throw Error("binning: area/solid fraction needs particle radii in every frame");
  ScalarField out(opt_.grid, 0.0);
  if (frames_ == 0) return out;
  double norm = 1.0 / (opt_.grid.dx() * opt_.grid.dy());
  if (dim_ == 3) {
    if (!all_slab_)
      throw Error("binning: the 3D solid fraction needs the slab thickness (a box in every frame, or slab_lo/slab_hi)");
    norm /= slab_sum_;
  } else {
    norm /= frames_;
  }
  for (std::size_t b = 0; b < vol_.size(); ++b) out.values[b] = vol_[b] * norm;
  return out;
}

void BinAccumulator::require_velocity(const char* what) const {
  if (!all_vel_) throw Error(std::string("binning: ") + what + " needs particle velocities in every frame");
}

VectorField BinAccumulator::mean_velocity() const {
  require_velocity("the mean velocity");
  VectorField out(opt_.grid, Vec2::Zero());
  for (std::size_t b = 0; b < count_.size(); ++b) {
    if (count_[b] == 0 || !(mass_[b] > 0.0)) {
      out.mask[b] = 0, out.values[b] = Vec2(kNaN, kNaN);
      continue;
    }
    const Vec3 u = mom_[b] / mass_[b];
    out.values[b] = Vec2(u[axis_u_], u[axis_v_]);
  }
  return out;
}

ScalarField BinAccumulator::temperature() const {
  require_velocity("the granular temperature");
  ScalarField out(opt_.grid, 0.0);
  for (std::size_t b = 0; b < count_.size(); ++b) {
    if (count_[b] < 2 || !(mass_[b] > 0.0)) {
      out.mask[b] = 0, out.values[b] = kNaN;
      continue;
    }
    // Σ m|v − u|² = Σ m|v|² − |u|² Σ m, with u the mass-weighted mean velocity.
    const double peculiar = msq_[b] - mom_[b].squaredNorm() / mass_[b];
    out.values[b] = std::max(0.0, peculiar) / (dim_ * static_cast<double>(count_[b]));
  }
  return out;
}

ScalarField BinAccumulator::mean_speed() const {
  require_velocity("the mean speed");
  ScalarField out(opt_.grid, 0.0);
  for (std::size_t b = 0; b < count_.size(); ++b) {
    if (count_[b] == 0) {
      out.mask[b] = 0, out.values[b] = kNaN;
      continue;
    }
    out.values[b] = speed_[b] / static_cast<double>(count_[b]);
  }
  return out;
}

BinnedFields bin_frame(const ParticleFrame& frame, const BinningOptions& options) {
  BinAccumulator acc(options);
  acc.add(frame);
  BinnedFields out{acc.density(), {}, {}, {}, {}, acc.counts()};
  const int w = options.plane == BinPlane::xy ? 2 : options.plane == BinPlane::xz ? 1 : 0;
  if (frame.dim == 2 || options.slab_lo || (frame.has_box && frame.box_hi[w] > frame.box_lo[w]))
    out.fraction = acc.fraction();
  if (frame.has_velocity()) {
    out.mean_velocity = acc.mean_velocity();
    out.temperature = acc.temperature();
    out.mean_speed = acc.mean_speed();
  }
  return out;
}

}  // namespace grainflow::core

namespace grainflow::core {

BinAccumulator::State BinAccumulator::state() const {
  State st{dim_, frames_, frame_vel_, frame_rad_, all_vel_, all_rad_, all_slab_, slab_sum_, outside_,
           count_, mass_, vol_, speed_, msq_, {}};
  st.mom.reserve(3 * mom_.size());
  for (const Vec3& m : mom_) st.mom.insert(st.mom.end(), {m.x(), m.y(), m.z()});
  return st;
}

void BinAccumulator::set_state(const State& st) {
  const std::size_t n = count_.size();
  if (st.count.size() != n || st.mass.size() != n || st.vol.size() != n || st.speed.size() != n ||
      st.msq.size() != n || st.mom.size() != 3 * n)
    throw Error("binned fields of " + std::to_string(st.count.size()) + " bins cannot be restored into " +
                std::to_string(n) + " bins");
  dim_ = st.dim;
  frames_ = st.frames;
  frame_vel_ = st.frame_vel;
  frame_rad_ = st.frame_rad;
  all_vel_ = st.all_vel;
  all_rad_ = st.all_rad;
  all_slab_ = st.all_slab;
  slab_sum_ = st.slab_sum;
  outside_ = st.outside;
  count_ = st.count;
  mass_ = st.mass;
  vol_ = st.vol;
  speed_ = st.speed;
  msq_ = st.msq;
  for (std::size_t i = 0; i < n; ++i) mom_[i] = Vec3(st.mom[3 * i], st.mom[3 * i + 1], st.mom[3 * i + 2]);
}

ScalarField vorticity(const VectorField& v) {
  const GridGeometry& g = v.grid;
  ScalarField out(g, std::numeric_limits<double>::quiet_NaN());
  // d/d(axis) of component c at (ix, iy): central where both neighbours are valid, else
  // one-sided with the valid one (and this bin), else unknown.
  auto derivative = [&](int ix, int iy, int dx, int dy, int c, double h, double& d) {
    const int ax = ix - dx, ay = iy - dy, bx = ix + dx, by = iy + dy;
    const bool a = ax >= 0 && ay >= 0 && v.valid(ax, ay), b = bx < g.nx && by < g.ny && v.valid(bx, by);
    if (a && b) d = (v.at(bx, by)[c] - v.at(ax, ay)[c]) / (2 * h);
    else if (b) d = (v.at(bx, by)[c] - v.at(ix, iy)[c]) / h;
    else if (a) d = (v.at(ix, iy)[c] - v.at(ax, ay)[c]) / h;
    else return false;
    return true;
  };
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) {
      double dv_du = 0, du_dv = 0;
      const bool ok = v.valid(ix, iy) && derivative(ix, iy, 1, 0, 1, g.dx(), dv_du) &&
                      derivative(ix, iy, 0, 1, 0, g.dy(), du_dv);
      out.mask[g.index(ix, iy)] = ok;
      if (ok) out.at(ix, iy) = dv_du - du_dv;
    }
  return out;
}

BinPlane bin_plane(std::string_view name) {
  if (name == "xy") return BinPlane::xy;
  if (name == "xz") return BinPlane::xz;
  if (name == "yz") return BinPlane::yz;
  throw Error("binning: \"" + std::string(name) + "\" is not a plane; allowed: xy, xz, yz");
}

std::array<int, 2> plane_axes(BinPlane plane) {
  return plane == BinPlane::xy ? std::array{0, 1} : plane == BinPlane::xz ? std::array{0, 2} : std::array{1, 2};
}

int plane_normal(BinPlane plane) { return plane == BinPlane::xy ? 2 : plane == BinPlane::xz ? 1 : 0; }

BinningOptions plane_binning(BinPlane plane, const Vec3& lo, const Vec3& hi, std::array<int, 2> bins,
                             std::optional<std::array<double, 2>> slab) {
  BinningOptions opt;
  const auto [u, v] = plane_axes(plane);
  opt.plane = plane;
  opt.grid.nx = bins[0];
  opt.grid.ny = bins[1];
  opt.grid.lo = Vec2(lo[u], lo[v]);
  opt.grid.hi = Vec2(hi[u], hi[v]);
  if (slab) {
    opt.slab_lo = (*slab)[0];
    opt.slab_hi = (*slab)[1];
  }
  return opt;
}

std::array<int, 2> bins_no_finer_than(const Vec2& extent, double min_width) {
  std::array<int, 2> out{1, 1};
  if (!(min_width > 0)) return out;
  for (int a = 0; a < 2; ++a)
    out[std::size_t(a)] = int(std::clamp(std::floor(extent[a] / min_width), 1.0, 4096.0));
  return out;
}

}  // namespace grainflow::core
