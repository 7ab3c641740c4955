#include "engine/ed/circular_obstacle.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "engine/core/error.hpp"
#include "engine/ed/checkpoint.hpp"
#include "engine/ed/system_state.hpp"
#include "engine/ed/thermal_wall.hpp"

namespace grainflow::ed {

CircularObstacle::CircularObstacle(const ObstacleConfig& cfg) : cfg_(cfg), rng_(cfg.seed) {}

void CircularObstacle::cells(const CellGrid& g, std::vector<int>& out) const {
  // A disk touching the obstacle has its centre within radius + cell diagonal of the
  // centre; any cell whose nearest point lies within radius + one cell size may host it.
  const double reach = cfg_.radius + std::max(g.width(), g.height());
  for (int iy = 0; iy < g.ny(); ++iy)
    for (int ix = 0; ix < g.nx(); ++ix) {
      const double qx = std::clamp(cfg_.centre.x(), ix * g.width(), (ix + 1) * g.width());
      const double qy = std::clamp(cfg_.centre.y(), iy * g.height(), (iy + 1) * g.height());
      if (std::hypot(qx - cfg_.centre.x(), qy - cfg_.centre.y()) <= reach) out.push_back(g.index(ix, iy));
    }
}

double CircularObstacle::event_time(const SystemState&, int, const DiskNow& d) const {
  return pair_collision_time(d.x - cfg_.centre.x(), d.y - cfg_.centre.y(), d.vx, d.vy, cfg_.radius + d.r);
}

void CircularObstacle::action(SystemState& s, int i) {
  const DiskNow d = s.disk_now(i);
  const double rx = d.x - cfg_.centre.x(), ry = d.y - cfg_.centre.y();
  const double inv = 1.0 / std::hypot(rx, ry);
  const double nx = rx * inv, ny = ry * inv;  // outward normal
  const double vn = d.vx * nx + d.vy * ny;     // < 0 on impact
  const double vt = -d.vx * ny + d.vy * nx;    // along (−n_y, n_x)
  double vn1 = -cfg_.restitution * vn, vt1 = vt;
  switch (cfg_.boundary) {
    case ObstacleBoundary::slip:
      break;
    case ObstacleBoundary::flip:
      if (rng_.uniform() < 0.5) vt1 = -vt;
      break;
    case ObstacleBoundary::thermal: {
      const WallFrameVelocity v = thermal_reemission(rng_, cfg_.kT, s.body[i].m);
      vn1 = v.normal;
      vt1 = v.tangential;
      break;
    }
  }
  const double vx = vn1 * nx - vt1 * ny, vy = vn1 * ny + vt1 * nx;
  impulse_ -= s.body[i].m * Vec2{vx - d.vx, vy - d.vy};
  ++hits_;
  s.set_velocity(i, vx, vy);
}

void CircularObstacle::set_restitution(double r) {
  if (!(r >= 0.0 && r <= 1.0))
    throw Error(fmt::format("ed: obstacle restitution = {} is invalid; allowed: 0 <= r <= 1", r));
  cfg_.restitution = r;
}

// Its random stream, the momentum and hits it has received (the drag measurement), and
// its restitution and surface (a phase may change them).
void CircularObstacle::save(io::ArchiveWriter& w) const {
  w.rng(rng_);
  checkpoint::write_vec2(w, impulse_);
  w.pod(hits_);
  w.pod(cfg_.restitution);
  w.pod(std::uint8_t(cfg_.boundary));
}

void CircularObstacle::load(io::ArchiveReader& r) {
  r.rng(rng_);
  impulse_ = checkpoint::read_vec2(r);
  r.pod(hits_);
  const double e = r.get<double>();
  if (!(e >= 0.0 && e <= 1.0)) r.corrupt(fmt::format("the obstacle's restitution is {}", e));
  cfg_.restitution = e;
  const auto b = r.get<std::uint8_t>();
  if (b > std::uint8_t(ObstacleBoundary::flip)) r.corrupt(fmt::format("the obstacle's surface kind is {}", int(b)));
  cfg_.boundary = ObstacleBoundary(b);
}

}  // namespace grainflow::ed
