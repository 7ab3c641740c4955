#include "engine/ed/elastic_walls.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "engine/core/error.hpp"
#include "engine/ed/checkpoint.hpp"
#include "engine/ed/system_state.hpp"
#include "engine/ed/thermal_wall.hpp"

namespace grainflow::ed {

std::string_view wall_surface_name(WallSurface s) {
  switch (s) {
    case WallSurface::slip: return "slip";
    case WallSurface::thermal: return "thermal";
    case WallSurface::flip: return "flip";
  }
  return "?";
}

ElasticWalls::ElasticWalls(double lx, double ly, bool walls_x, bool walls_y, double restitution)
    : lx_(lx), ly_(ly), wx_(walls_x), wy_(walls_y), rng_(cfg_.seed) {
  cfg_.restitution = restitution;
}

void ElasticWalls::configure(const WallConfig& cfg) {
  auto bad = [](std::string_view what, double v, std::string_view allowed) {
    throw Error(fmt::format("ed walls: {} = {} is invalid; allowed: {}", what, v, allowed));
  };
  if (!(cfg.restitution >= 0.0 && cfg.restitution <= 1.0)) bad("restitution", cfg.restitution, "0 <= r <= 1");
  if (!(cfg.kT > 0.0) || !std::isfinite(cfg.kT)) bad("kT", cfg.kT, "a positive temperature");
  if (!std::isfinite(cfg.u_low)) bad("u_low", cfg.u_low, "a finite velocity");
  if (!std::isfinite(cfg.u_high)) bad("u_high", cfg.u_high, "a finite velocity");
  if (!wy_ && (cfg.u_low != 0.0 || cfg.u_high != 0.0))
    bad("wall velocity", cfg.u_low != 0.0 ? cfg.u_low : cfg.u_high, "0 without walls in y (only they move)");
  cfg_ = cfg;
  rng_ = core::Rng(cfg.seed);
}

void ElasticWalls::cells(const CellGrid& g, std::vector<int>& out) const {
  for (int iy = 0; iy < g.ny(); ++iy)
    for (int ix = 0; ix < g.nx(); ++ix)
      if ((wx_ && (ix == 0 || ix == g.nx() - 1)) || (wy_ && (iy == 0 || iy == g.ny() - 1)))
        out.push_back(g.index(ix, iy));
}

namespace {
// Delay until a disk at coordinate p with velocity v and radius r touches [0, L].
double wall_time(double p, double v, double r, double l) {
  if (v > 0.0) return std::max(0.0, (l - r - p) / v);
  if (v < 0.0) return std::max(0.0, (r - p) / v);
  return kNever;
}
}  // namespace

double ElasticWalls::event_time(const SystemState&, int, const DiskNow& d) const {
  const double tx = wx_ ? wall_time(d.x, d.vx, d.r, lx_) : kNever;
  const double ty = wy_ ? wall_time(d.y, d.vy, d.r, ly_) : kNever;
  return std::min(tx, ty);
}

void ElasticWalls::action(SystemState& s, int i) {
  const DiskNow d = s.disk_now(i);
  const double tx = wx_ ? wall_time(d.x, d.vx, d.r, lx_) : kNever;
  const double ty = wy_ ? wall_time(d.y, d.vy, d.r, ly_) : kNever;
  const bool on_x = tx <= ty;
  const WallId w = on_x ? (d.vx > 0.0 ? wall_x_high : wall_x_low) : (d.vy > 0.0 ? wall_y_high : wall_y_low);
  const double r = cfg_.restitution;
  double vx = d.vx, vy = d.vy;
  if (cfg_.surface == WallSurface::slip) {
    // The tangential velocity is kept whatever the wall's: the path of the resting walls.
    if (on_x) vx = -r * vx; else vy = -r * vy;
  } else {
    // Normal (into the wall, > 0) and tangential components, relative to the wall.
    const double into = on_x ? (w == wall_x_high ? 1.0 : -1.0) : (w == wall_y_high ? 1.0 : -1.0);
    const double u = w == wall_y_low ? cfg_.u_low : w == wall_y_high ? cfg_.u_high : 0.0;
    const double vn = into * (on_x ? d.vx : d.vy);
    const double vt = (on_x ? d.vy : d.vx) - u;
    double vn1 = -r * vn, vt1 = vt;
    if (cfg_.surface == WallSurface::thermal) {
      const WallFrameVelocity v = thermal_reemission(rng_, cfg_.kT, d.m);
      vn1 = -v.normal;
      vt1 = v.tangential;
    } else if (rng_.uniform() < 0.5) {
      vt1 = -vt;
    }
    const double n1 = into * vn1, t1 = vt1 + u;
    if (on_x) { vx = n1; vy = t1; } else { vx = t1; vy = n1; }
  }
  const double m = d.m;
  impulse_x_ -= m * (vx - d.vx);
  impulse_y_ -= m * (vy - d.vy);
  given_p_[w] += m * Vec2{vx - d.vx, vy - d.vy};
  given_e_[w] += 0.5 * m * ((vx * vx + vy * vy) - (d.vx * d.vx + d.vy * d.vy));
  ++hits_[w];
  s.set_velocity(i, vx, vy);
}

// The walls' random stream and the momentum and energy they gave (wall pressure, shear
// stress, heat); their surface and velocities are configuration.
void ElasticWalls::save(io::ArchiveWriter& w) const {
  w.pod(impulse_x_);
  w.pod(impulse_y_);
  w.rng(rng_);
  for (int k = 0; k < 4; ++k) {
    checkpoint::write_vec2(w, given_p_[k]);
    w.pod(given_e_[k]);
    w.pod(hits_[k]);
  }
}

void ElasticWalls::load(io::ArchiveReader& r) {
  r.pod(impulse_x_);
  r.pod(impulse_y_);
  r.rng(rng_);
  for (int k = 0; k < 4; ++k) {
    given_p_[k] = checkpoint::read_vec2(r);
    r.pod(given_e_[k]);
    r.pod(hits_[k]);
  }
}

}  // namespace grainflow::ed
