// Evenly spaced streamlines (Jobard & Lefer 1997) of a binned velocity field.
//
// Integrator: classical RK4 on the unit direction field dx/ds = v/|v| with a fixed arc
// step. An adaptive Dormand–Prince scheme buys nothing here: the bilinear field is only
// C0 across bin edges, so its error estimate would be dominated by the kinks, and the
// geometric error of the lines is set by the interpolation (O(h_bin²)), not by the
// integrator (O(step⁴) per unit length, step = 0.25 bin). A fixed step also gives evenly
// spaced vertices, which the d_test vertex test and the renderer both rely on.
#include "render/layers/streamlines.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <string>

#include "engine/core/error.hpp"

namespace grainflow::render {

namespace {

bool finite(const Vec2& v) { return std::isfinite(v.x()) && std::isfinite(v.y()); }

[[noreturn]] void bad_option(const std::string& key, double value, const std::string& allowed) {
  throw Error("streamlines: option '" + key + "' = " + std::to_string(value) + " is invalid; allowed: " +
              allowed);
}

}  // namespace

// ---------------------------------------------------------------------------------------
// VelocitySampler

VelocitySampler::VelocitySampler(const core::VectorField& field, std::span<const SolidCircle> solids,
                                 const Vec2& reference_velocity)
    : grid_(field.grid), solids_(solids.begin(), solids.end()) {
  const std::size_t n = grid_.size();
  if (grid_.nx < 1 || grid_.ny < 1 || field.values.size() != n || field.mask.size() != n ||
      !(grid_.hi.x() > grid_.lo.x()) || !(grid_.hi.y() > grid_.lo.y()))
    throw Error("streamlines: velocity field grid is inconsistent (nx = " + std::to_string(grid_.nx) +
                ", ny = " + std::to_string(grid_.ny) + ", " + std::to_string(field.values.size()) +
                " values, " + std::to_string(field.mask.size()) +
                " mask entries); allowed: nx, ny >= 1, nx*ny values and mask entries, hi > lo");
  if (!finite(reference_velocity))
    throw Error("streamlines: option 'reference_velocity' is not finite; allowed: finite numbers");
  vel_.assign(n, Vec2::Zero());
  valid_.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 v = field.values[i] - reference_velocity;
    if (field.mask[i] != 0 && finite(field.values[i]) && finite(v)) {
      valid_[i] = 1;
      vel_[i] = v;
      max_speed_ = std::max(max_speed_, v.norm());
    }
  }
  inv_dx_ = 1.0 / grid_.dx();
  inv_dy_ = 1.0 / grid_.dy();
  cx_ = std::max(1, grid_.nx - 1);
  cy_ = std::max(1, grid_.ny - 1);
  cell_ok_.assign(static_cast<std::size_t>(cx_) * cy_, 0);
  for (int j = 0; j < cy_; ++j)
    for (int i = 0; i < cx_; ++i) {
      const int i1 = std::min(i + 1, grid_.nx - 1), j1 = std::min(j + 1, grid_.ny - 1);
      cell_ok_[static_cast<std::size_t>(j) * cx_ + i] =
          valid_[grid_.index(i, j)] & valid_[grid_.index(i1, j)] & valid_[grid_.index(i, j1)] &
          valid_[grid_.index(i1, j1)];
    }
  for (const auto& c : solids_)
    if (!finite(c.centre) || !std::isfinite(c.radius) || c.radius < 0.0)
      throw Error("streamlines: solid circle (centre " + std::to_string(c.centre.x()) + ", " +
                  std::to_string(c.centre.y()) + ", radius " + std::to_string(c.radius) +
                  ") is invalid; allowed: finite centre, radius >= 0");
}

bool VelocitySampler::inside_domain(const Vec2& p) const {
  return p.x() >= grid_.lo.x() && p.x() <= grid_.hi.x() && p.y() >= grid_.lo.y() && p.y() <= grid_.hi.y();
}

bool VelocitySampler::in_solid(const Vec2& p) const {
  for (const auto& c : solids_)
    if ((p - c.centre).squaredNorm() < c.radius * c.radius) return true;
  return false;
}

bool VelocitySampler::stencil(const Vec2& p, int& i0, int& j0, double& tx, double& ty) const {
  if (!inside_domain(p) || in_solid(p)) return false;
  const double fx = (p.x() - grid_.lo.x()) * inv_dx_ - 0.5;
  const double fy = (p.y() - grid_.lo.y()) * inv_dy_ - 0.5;
  // Clamping the lower index (not the coordinate) extrapolates linearly in the border.
  i0 = grid_.nx >= 2 ? std::clamp(static_cast<int>(std::floor(fx)), 0, grid_.nx - 2) : 0;
  j0 = grid_.ny >= 2 ? std::clamp(static_cast<int>(std::floor(fy)), 0, grid_.ny - 2) : 0;
  tx = grid_.nx >= 2 ? fx - i0 : 0.0;
  ty = grid_.ny >= 2 ? fy - j0 : 0.0;
  return cell_ok_[static_cast<std::size_t>(j0) * cx_ + i0] != 0;
}

bool VelocitySampler::blocked(const Vec2& p) const {
  int i0, j0;
  double tx, ty;
  return !stencil(p, i0, j0, tx, ty);
}

bool VelocitySampler::sample(const Vec2& p, Vec2& v) const {
  int i0, j0;
  double tx, ty;
  if (!stencil(p, i0, j0, tx, ty)) return false;
  const int i1 = std::min(i0 + 1, grid_.nx - 1), j1 = std::min(j0 + 1, grid_.ny - 1);
  const Vec2& a = vel_[grid_.index(i0, j0)];
  const Vec2& b = vel_[grid_.index(i1, j0)];
  const Vec2& c = vel_[grid_.index(i0, j1)];
  const Vec2& d = vel_[grid_.index(i1, j1)];
  v = (1.0 - ty) * ((1.0 - tx) * a + tx * b) + ty * ((1.0 - tx) * c + tx * d);
  return true;
}

// ---------------------------------------------------------------------------------------
// Tracer

namespace {

// Background grid of all accepted vertices (Jobard & Lefer §3): O(1) distance queries.
class PointGrid {
public:
  struct Pt {
    Vec2 p;
    double s;  // signed arc position on its line (backward half negative)
    int line;
  };

  PointGrid(const core::GridGeometry& g, double cell) : lo_(g.lo), cell_(cell) {
    nx_ = std::max(1, static_cast<int>(std::ceil((g.hi.x() - g.lo.x()) / cell)));
    ny_ = std::max(1, static_cast<int>(std::ceil((g.hi.y() - g.lo.y()) / cell)));
    head_.assign(static_cast<std::size_t>(nx_) * ny_, -1);
  }

  void insert(const Vec2& p, double s, int line) {
    const int c = cell_of(p);
    pts_.push_back({p, s, line});
    next_.push_back(head_[c]);
    cells_.push_back(c);
    head_[c] = static_cast<int>(pts_.size()) - 1;
  }

  // Remove the most recent points down to `count` (a discarded line).
  void truncate(std::size_t count) {
    while (pts_.size() > count) {
      head_[cells_.back()] = next_.back();
      pts_.pop_back();
      next_.pop_back();
      cells_.pop_back();
    }
  }
  std::size_t size() const { return pts_.size(); }

  // First point within radius r of p for which skip(pt) is false; nullptr if none.
  template <class Skip>
  const Pt* find_within(const Vec2& p, double r, Skip skip) const {
    const double r2 = r * r;
    const int ix0 = clampx(std::floor((p.x() - r - lo_.x()) / cell_));
    const int ix1 = clampx(std::floor((p.x() + r - lo_.x()) / cell_));
    const int iy0 = clampy(std::floor((p.y() - r - lo_.y()) / cell_));
    const int iy1 = clampy(std::floor((p.y() + r - lo_.y()) / cell_));
    for (int iy = iy0; iy <= iy1; ++iy)
      for (int ix = ix0; ix <= ix1; ++ix)
        for (int k = head_[static_cast<std::size_t>(iy) * nx_ + ix]; k >= 0; k = next_[k]) {
          const Pt& q = pts_[k];
          if ((q.p - p).squaredNorm() < r2 && !skip(q)) return &q;
        }
    return nullptr;
  }

private:
  // Clamped as doubles first: a far-away query point must not overflow the int cast.
  int clampx(double f) const { return static_cast<int>(std::clamp(f, 0.0, nx_ - 1.0)); }
  int clampy(double f) const { return static_cast<int>(std::clamp(f, 0.0, ny_ - 1.0)); }
  int cell_of(const Vec2& p) const {
    const int ix = clampx(std::floor((p.x() - lo_.x()) / cell_));
    const int iy = clampy(std::floor((p.y() - lo_.y()) / cell_));
    return iy * nx_ + ix;
  }

  Vec2 lo_;
  double cell_;
  int nx_ = 1, ny_ = 1;
  std::vector<int> head_;
  std::vector<Pt> pts_;
  std::vector<int> next_;
  std::vector<int> cells_;
};

class Tracer {
public:
  Tracer(const VelocitySampler& f, const StreamlineOptions& o, double d_sep)
      : f_(f),
        d_sep_(d_sep),
        d_test_(o.test_fraction * d_sep),
        step_(std::min(o.step_bins * std::min(f.grid().dx(), f.grid().dy()), 0.5 * o.test_fraction * d_sep)),
        own_window_(2.0 * d_test_),
        close_tol_(0.05 * d_sep),
        max_length_(o.max_length > 0.0 ? o.max_length : std::numeric_limits<double>::infinity()),
        min_length_(o.min_length),
        v_min_(o.min_speed_fraction * f.max_speed()),
        grid_(f.grid(), std::max(d_sep, std::max(f.grid().hi.x() - f.grid().lo.x(),
                                                 f.grid().hi.y() - f.grid().lo.y()) / 1024.0)) {
    // Hard cap on the arc of one direction, independent of max_length. Vertices of a line
    // more than 2·d_test apart along it are at least d_test apart in space (self-proximity
    // test), so picking one every 2·d_test + step <= 2.5·d_test of arc gives at most the
    // disc-packing count 4(W + d_test)(H + d_test)/(π d_test²): no line is longer than
    // about 3.2·(W + d_test)(H + d_test)/d_test. The cap 8·(W + 2 d_test)(H + 2 d_test)/d_test
    // is well above that; with every step advancing at least kMinProgress·step (below), it
    // bounds the number of steps of any line.
    const double w = f.grid().hi.x() - f.grid().lo.x(), hgt = f.grid().hi.y() - f.grid().lo.y();
    arc_cap_ = 8.0 * (w + 2.0 * d_test_) * (hgt + 2.0 * d_test_) / d_test_;
  }

  // A usable seed: inside, unblocked, not stagnant, at least `clearance` from all lines.
  // `blocker` (optional) is the vertex that rejected the previous candidate on this side;
  // neighbouring candidates are usually rejected by the same one, so it is tried first.
  bool seed_ok(const Vec2& p, double clearance, Vec2* blocker = nullptr) const {
    // Proximity first: it rejects most candidates (those next to existing lines).
    if (blocker && (*blocker - p).squaredNorm() < clearance * clearance) return false;
    if (const auto* x = grid_.find_within(p, clearance, [](const PointGrid::Pt&) { return false; })) {
      if (blocker) *blocker = x->p;
      return false;
    }
    Vec2 v;
    return f_.sample(p, v) && v.norm() > v_min_ && v.norm() > 0.0;
  }

  // Traces the line through `seed`; appends it to `out` unless it is too short.
  bool trace(const Vec2& seed, std::vector<Streamline>& out) {
    const int id = static_cast<int>(out.size());
    const std::size_t grid_mark = grid_.size();
    Vec2 v0;
    f_.sample(seed, v0);
    const StreamlinePoint s0{seed, v0.norm(), 0.0};
    grid_.insert(seed, 0.0, id);

    std::vector<StreamlinePoint> fwd{s0}, bwd;
    const bool closed = trace_dir(+1, id, fwd, 0.5 * max_length_);
    if (!closed) {
      bwd.push_back(s0);
      trace_dir(-1, id, bwd, max_length_ - fwd.back().arc_length);
    }

    Streamline line;
    line.closed = closed;
    line.points.reserve(fwd.size() + bwd.size());
    for (std::size_t i = bwd.size(); i-- > 1;) line.points.push_back(bwd[i]);
    line.points.insert(line.points.end(), fwd.begin(), fwd.end());
    double s = 0.0;
    for (std::size_t i = 0; i < line.points.size(); ++i) {
      if (i > 0) s += (line.points[i].position - line.points[i - 1].position).norm();
      line.points[i].arc_length = s;
    }
    if (line.points.size() < 2 || s <= 0.0 || s < min_length_) {
      grid_.truncate(grid_mark);
      return false;
    }
    out.push_back(std::move(line));
    return true;
  }

  double d_sep() const { return d_sep_; }
  double step() const { return step_; }

private:
  enum class Step { Ok, Blocked, Stagnant };

  Step direction(const Vec2& v, Vec2& k) const {
    const double n = v.norm();
    if (!(n > v_min_) || n == 0.0) return Step::Stagnant;
    k = v / n;
    return Step::Ok;
  }
  Step direction_at(const Vec2& p, Vec2& k) const {
    Vec2 v;
    return f_.sample(p, v) ? direction(v, k) : Step::Blocked;
  }

  // One RK4 step from p (velocity vp, known from the previous step) to q (velocity vq).
  Step rk4(const Vec2& p, const Vec2& vp, double h, Vec2& q, Vec2& vq) const {
    Vec2 k1, k2, k3, k4;
    Step r;
    if ((r = direction(vp, k1)) != Step::Ok) return r;
    if ((r = direction_at(p + 0.5 * h * k1, k2)) != Step::Ok) return r;
    if ((r = direction_at(p + 0.5 * h * k2, k3)) != Step::Ok) return r;
    if ((r = direction_at(p + h * k3, k4)) != Step::Ok) return r;
    q = p + (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    return f_.sample(q, vq) ? Step::Ok : Step::Blocked;
  }

  // Walks from pts.back() (the seed) in direction dir (+1 along v, -1 against it) until a
  // stop condition; returns true when the line closed onto its seed (forward only).
  bool trace_dir(int dir, int id, std::vector<StreamlinePoint>& pts, double budget) {
    budget = std::min(budget, arc_cap_);
    const Vec2 seed = pts.front().position;
    Vec2 p = seed, vp;
    f_.sample(p, vp);
    double s = 0.0;  // arc length walked in this direction
    bool closing = false;
    double closing_d = std::numeric_limits<double>::infinity();
    int closing_steps = 0;
    std::size_t closing_mark_pts = 0, closing_mark_grid = 0;
    constexpr std::size_t kMaxPoints = 4'000'000;  // memory guard only; lines end earlier
    // Work bound: every step but the last advances >= kMinProgress·step_, so the budget
    // (finite after the arc cap) is used up within this many steps; the closing approach
    // adds at most d_test/step + 5.
    const double max_steps_d = std::ceil(budget / (kMinProgress * step_)) + d_test_ / step_ + 16.0;
    const std::size_t max_steps =
        static_cast<std::size_t>(std::min(max_steps_d, static_cast<double>(kMaxPoints)));
    std::size_t steps = 0;
    // A line that stops while approaching its seed is not a loop: drop the approach, which
    // ignored the self-proximity test.
    const auto stop = [&] {
      if (closing) {
        pts.resize(closing_mark_pts);
        grid_.truncate(closing_mark_grid);
      }
      return false;
    };
    while (pts.size() < kMaxPoints && steps++ < max_steps) {
      double h = std::min(step_, budget - s);
      if (!(h > 1e-9 * step_)) return stop();  // length budget used up
      Vec2 q, vq;
      // A partial step uses up the budget: it is the last one (no tail of ever smaller
      // steps converging onto the limit).
      bool last = h < step_;
      Step r = rk4(p, vp, dir * h, q, vq);
      if (r == Step::Stagnant) return stop();
      if (r == Step::Blocked) {
        // Edge, obstacle or masked bin ahead: bisect to end the line close to it.
        double lo = 0.0, hi = h;
        Vec2 best = p, best_v = vp;
        for (int it = 0; it < 12; ++it) {
          const double mid = 0.5 * (lo + hi);
          Vec2 t, tv;
          if (rk4(p, vp, dir * mid, t, tv) == Step::Ok) {
            lo = mid;
            best = t;
            best_v = tv;
          } else {
            hi = mid;
          }
        }
        if (lo < 1e-3 * step_) return stop();
        q = best;
        vq = best_v;
        h = lo;
        last = true;
      }
      // No progress: the direction field turns back within one step (a line onto which
      // the flow converges from both sides, a cusp or a near-stagnation knot of a noisy
      // field: k1 + 2k2 + 2k3 + k4 ≈ 0). Continuing would creep towards the fold with ever
      // shorter chords, the arc (and with it the self-proximity window and the length
      // budget) would hardly grow, and the line would never end. Stop as at stagnation.
      if ((q - p).norm() < kMinProgress * h) return stop();
      const double sq = s + (q - p).norm();
      const double signed_s = dir * sq;
      // Another line too close: stop (Jobard & Lefer's d_test).
      bool self_hit_near_seed = false, self_hit = false;
      const auto* hit = grid_.find_within(q, d_test_, [&](const PointGrid::Pt& x) {
        if (x.line != id) return false;
        if (closing || std::abs(x.s - signed_s) <= own_window_) return true;
        self_hit = true;
        if (dir > 0 && std::abs(x.s) < own_window_) self_hit_near_seed = true;
        return true;  // keep scanning: another line may still be within d_test
      });
      if (hit) return stop();
      if (self_hit && !closing) {
        if (!self_hit_near_seed) return stop();  // spiral onto itself
        closing = true;
        closing_mark_pts = pts.size();
        closing_mark_grid = grid_.size();
      }
      if (closing) {
        // Follow the loop up to the last vertex before it passes the seed, and close it
        // there if it came back onto the seed (a spiral misses it sideways: not closed).
        const Vec2 t0 = (pts[1].position - seed).normalized();
        const double d = (q - seed).norm();
        if ((q - seed).dot(t0) > 0.0 || d >= closing_d ||
            ++closing_steps > static_cast<int>(d_test_ / step_) + 4) {
          const Vec2 off = p - seed;
          const double side = std::abs(off.x() * t0.y() - off.y() * t0.x());
          if (closing_d <= 1.01 * step_ && side <= close_tol_) {
            pts.push_back({seed, pts.front().speed, s + closing_d});
            return true;
          }
          return stop();
        }
        closing_d = d;
      }
      pts.push_back({q, vq.norm(), sq});
      grid_.insert(q, signed_s, id);
      p = q;
      vp = vq;
      s = sq;
      if (last) return stop();
    }
    return stop();
  }

  // Smallest chord of a step, as a fraction of the step: the chord of an arc turning by θ
  // is sinc(θ/2) of it, so 0.5 only rejects turns beyond 3.8 rad in one step (a radius of
  // curvature under 0.26 step), which the fixed step cannot resolve anyway.
  static constexpr double kMinProgress = 0.5;

  const VelocitySampler& f_;
  double d_sep_, d_test_, step_, own_window_, close_tol_, max_length_, min_length_, v_min_;
  double arc_cap_ = std::numeric_limits<double>::infinity();
  PointGrid grid_;
};

void validate(const StreamlineOptions& o, const core::GridGeometry& g, double d_sep) {
  const double extent = std::max(g.hi.x() - g.lo.x(), g.hi.y() - g.lo.y());
  if (o.separation < 0.0 || !std::isfinite(o.separation))
    bad_option("separation", o.separation, "0 (use separation_fraction) or a positive length");
  if (o.separation == 0.0 && !(o.separation_fraction > 0.0 && o.separation_fraction <= 1.0))
    bad_option("separation_fraction", o.separation_fraction, "0 < fraction <= 1");
  if (!(d_sep >= 1e-4 * extent && d_sep <= extent))
    bad_option("separation", d_sep, "between 1e-4 and 1 times the domain extent " + std::to_string(extent));
  if (!(o.test_fraction > 0.0 && o.test_fraction <= 1.0))
    bad_option("test_fraction", o.test_fraction, "0 < fraction <= 1");
  if (!(o.step_bins > 0.0 && o.step_bins <= 1.0)) bad_option("step_bins", o.step_bins, "0 < step <= 1 bin");
  if (!(o.max_length >= 0.0) || std::isnan(o.max_length))
    bad_option("max_length", o.max_length, "0 (no limit) or a positive length");
  if (!(o.min_length >= 0.0 && std::isfinite(o.min_length)))
    bad_option("min_length", o.min_length, "a length >= 0");
  if (!(o.min_speed_fraction >= 0.0 && o.min_speed_fraction < 1.0))
    bad_option("min_speed_fraction", o.min_speed_fraction, "0 <= fraction < 1");
  if (o.max_lines < 0) bad_option("max_lines", o.max_lines, "an integer >= 0");
  if (o.seed_start && !finite(*o.seed_start))
    throw Error("streamlines: option 'seed_start' is not finite; allowed: a point in the domain");
}

}  // namespace

std::vector<Streamline> trace_streamlines(const core::VectorField& field, std::span<const SolidCircle> solids,
                                          const StreamlineOptions& options) {
  const VelocitySampler sampler(field, solids, options.reference_velocity);
  const auto& g = sampler.grid();
  const double d_sep =
      options.separation > 0.0 ? options.separation : options.separation_fraction * (g.hi.x() - g.lo.x());
  validate(options, g, d_sep);

  std::vector<Streamline> lines;
  if (options.max_lines == 0 || !(sampler.max_speed() > 0.0)) return lines;
  Tracer tracer(sampler, options, d_sep);
  const auto full = [&] { return static_cast<int>(lines.size()) >= options.max_lines; };

  // Jobard & Lefer: a FIFO of lines; each offers seeds at d_sep on both sides of every
  // vertex. When it runs dry, a d_sep lattice (row by row) supplies seeds for regions the
  // front cannot reach (behind obstacles, across stagnation zones).
  std::deque<std::size_t> queue;
  const auto try_seed = [&](const Vec2& p, Vec2* blocker = nullptr) {
    if (!tracer.seed_ok(p, 0.999 * d_sep, blocker)) return;
    if (tracer.trace(p, lines)) queue.push_back(lines.size() - 1);
  };
  try_seed(options.seed_start.value_or(Vec2(0.5 * (g.lo + g.hi))));

  const int lx = std::max(1, static_cast<int>((g.hi.x() - g.lo.x()) / d_sep));
  const int ly = std::max(1, static_cast<int>((g.hi.y() - g.lo.y()) / d_sep));
  const double ox = g.lo.x() + 0.5 * ((g.hi.x() - g.lo.x()) - (lx - 1) * d_sep);
  const double oy = g.lo.y() + 0.5 * ((g.hi.y() - g.lo.y()) - (ly - 1) * d_sep);
  long long lattice = 0;
  const long long lattice_end = static_cast<long long>(lx) * ly;

  while (!full()) {
    if (queue.empty()) {
      if (lattice >= lattice_end) break;
      const Vec2 p(ox + static_cast<double>(lattice % lx) * d_sep, oy + static_cast<double>(lattice / lx) * d_sep);
      ++lattice;
      try_seed(p);
      continue;
    }
    const std::size_t li = queue.front();
    queue.pop_front();
    const std::size_t n = lines[li].points.size() - (lines[li].closed ? 1 : 0);
    Vec2 blocker_left = Vec2::Constant(std::numeric_limits<double>::infinity());
    Vec2 blocker_right = blocker_left;
    for (std::size_t i = 0; i < n && !full(); ++i) {
      // Copy: tracing appends to `lines` and may reallocate it.
      const Vec2 a = lines[li].points[i > 0 ? i - 1 : i].position;
      const Vec2 b = lines[li].points[i + 1 < lines[li].points.size() ? i + 1 : i].position;
      const Vec2 p = lines[li].points[i].position;
      const Vec2 t = b - a;
      const double tn = t.norm();
      if (!(tn > 0.0)) continue;
      const Vec2 nrm(-t.y() / tn, t.x() / tn);
      try_seed(p + d_sep * nrm, &blocker_left);
      if (!full()) try_seed(p - d_sep * nrm, &blocker_right);
    }
  }
  return lines;
}

std::vector<Arrowhead> place_arrowheads(std::span<const Streamline> lines, double spacing) {
  if (!(spacing > 0.0) || !std::isfinite(spacing))
    bad_option("arrow spacing", spacing, "a positive finite length");
  std::vector<Arrowhead> out;
  for (const auto& line : lines) {
    const auto& pts = line.points;
    const double len = line.length();
    if (pts.size() < 2 || !(len > 0.0)) continue;
    // Centred on the line rather than counted from its start: rows of lines that start on
    // the same edge do not get rows of arrows there, and a short line gets one mid-way.
    const double count = std::max(1.0, std::floor(len / spacing));
    double target = 0.5 * (len - (count - 1.0) * spacing);
    std::size_t i = 1;
    for (double k = 0; k < count; ++k, target += spacing) {
      while (i + 1 < pts.size() && pts[i].arc_length < target) ++i;
      const auto& a = pts[i - 1];
      const auto& b = pts[i];
      const double seg = b.arc_length - a.arc_length;
      const Vec2 d = b.position - a.position;
      if (seg > 0.0 && d.norm() > 0.0) {
        const double t = std::clamp((target - a.arc_length) / seg, 0.0, 1.0);
        out.push_back({a.position + t * d, d.normalized(), a.speed + t * (b.speed - a.speed)});
      }
    }
  }
  return out;
}

std::vector<QuiverArrow> quiver(const core::VectorField& field, std::span<const SolidCircle> solids,
                                const Vec2& reference_velocity, int stride) {
  if (stride < 1) bad_option("quiver stride", stride, "an integer >= 1 (bins)");
  const VelocitySampler sampler(field, solids, reference_velocity);
  const auto& g = sampler.grid();
  std::vector<QuiverArrow> out;
  for (int iy = stride / 2; iy < g.ny; iy += stride)
    for (int ix = stride / 2; ix < g.nx; ix += stride) {
      const Vec2 c = g.centre(ix, iy);
      if (!sampler.bin_valid(ix, iy) || !sampler.inside_domain(c)) continue;
      bool solid = false;
      for (const auto& s : solids) solid = solid || (c - s.centre).squaredNorm() < s.radius * s.radius;
      if (solid) continue;
      const Vec2& v = sampler.bin_velocity(ix, iy);
      out.push_back({c, v, v.norm()});
    }
  return out;
}

}  // namespace grainflow::render
