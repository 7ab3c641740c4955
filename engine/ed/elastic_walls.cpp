#include "engine/ed/elastic_walls.hpp"

#include <algorithm>
#include <cmath>

#include "engine/ed/checkpoint.hpp"
#include "engine/ed/system_state.hpp"

namespace grainflow::ed {

ElasticWalls::ElasticWalls(double lx, double ly, bool walls_x, bool walls_y, double restitution)
    : lx_(lx), ly_(ly), wx_(walls_x), wy_(walls_y), r_(restitution) {}

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

double ElasticWalls::event_time(const SystemState& s, int i) const {
  const Disk& d = s.disk[i];
  const double tx = wx_ ? wall_time(d.x, d.vx, d.r, lx_) : kNever;
  const double ty = wy_ ? wall_time(d.y, d.vy, d.r, ly_) : kNever;
  return std::min(tx, ty);
}

void ElasticWalls::action(SystemState& s, int i) {
  const Disk& d = s.disk[i];
  const double tx = wx_ ? wall_time(d.x, d.vx, d.r, lx_) : kNever;
  const double ty = wy_ ? wall_time(d.y, d.vy, d.r, ly_) : kNever;
  double vx = d.vx, vy = d.vy;
  if (tx <= ty) vx = -r_ * vx; else vy = -r_ * vy;
  impulse_x_ -= s.disk[i].m * (vx - d.vx);
  impulse_y_ -= s.disk[i].m * (vy - d.vy);
  s.set_velocity(i, vx, vy);
}

// The momentum given to the walls so far (wall pressure); the walls themselves are fixed.
void ElasticWalls::save(io::ArchiveWriter& w) const {
  w.pod(impulse_x_);
  w.pod(impulse_y_);
}

void ElasticWalls::load(io::ArchiveReader& r) {
  r.pod(impulse_x_);
  r.pod(impulse_y_);
}

}  // namespace grainflow::ed
