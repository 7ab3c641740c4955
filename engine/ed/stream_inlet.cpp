#include "engine/ed/stream_inlet.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "engine/core/error.hpp"
#include "engine/ed/cell_grid.hpp"
#include "engine/ed/checkpoint.hpp"
#include "engine/ed/initial_state.hpp"
#include "engine/ed/system_state.hpp"

namespace grainflow::ed {

void plane_cells(const CellGrid& g, double x, std::vector<int>& out) {
  // A margin of 1e−9 cell widths: a plane on a column boundary belongs to both columns, so
  // a disk is asked whichever side of the boundary round-off puts it.
  const double eps = 1e-9 * g.width();
  const int lo = std::clamp(static_cast<int>(std::floor((x - eps) / g.width())), 0, g.nx() - 1);
  const int hi = std::clamp(static_cast<int>(std::floor((x + eps) / g.width())), 0, g.nx() - 1);
  for (int iy = 0; iy < g.ny(); ++iy)
    for (int ix = lo; ix <= hi; ++ix) out.push_back(g.index(ix, iy));
}

StreamInlet::StreamInlet(const StreamInletConfig& cfg, std::shared_ptr<const StreamFlux> flux)
    : cfg_(cfg), flux_(std::move(flux)), rng_(cfg.seed) {
  auto bad = [](const char* what, double v, const char* allowed) {
    std::ostringstream os;
    os << "stream inlet: " << what << " = " << v << " is not allowed (" << allowed << ")";
    throw Error(os.str());
  };
  if (!flux_) throw Error("stream inlet: no flux distribution given");
  if (!(cfg.y_max > cfg.y_min)) bad("plane extent y_max − y_min", cfg.y_max - cfg.y_min, "> 0");
  if (!(cfg.number_density > 0.0) || !std::isfinite(cfg.number_density)) bad("number density", cfg.number_density, "finite, > 0");
  if (!(cfg.radius > 0.0)) bad("disk radius", cfg.radius, "> 0");
  if (cfg.max_tries < 1) bad("max_tries", cfg.max_tries, "≥ 1");
  rate_ = cfg.number_density * flux_->flux_forward() * (cfg.y_max - cfg.y_min);
  next_ = cfg.t_start - std::log(rng_.uniform_pos()) / rate_;
}

bool StreamInlet::spot_is_free(const SystemState& s, double x, double y) const {
  const CellGrid& g = s.grid;
  const int c = g.cell_of_point(x, y);
  bool free = true;
  g.for_neighbour_cells(c, [&](int cc) {
    for (int k = 0; k < g.count(cc) && free; ++k) {
      const int j = g.member(cc, k);
      const Vec2 p = s.position_now(j);
      double dx = p.x() - x, dy = p.y() - y;
      if (g.periodic_x()) dx -= g.lx() * std::round(dx / g.lx());
      if (g.periodic_y()) dy -= g.ly() * std::round(dy / g.ly());
      const double sig = cfg_.radius + s.body[j].r;
      if (dx * dx + dy * dy < sig * sig) free = false;
    }
  });
  return free;
}

void StreamInlet::action(SystemState& s) {
  ++arrivals_;
  DiskInit d;
  d.v = flux_->sample_forward(rng_);
  d.radius = cfg_.radius;
  d.mass = flux_->mass();
  bool placed = false;
  for (int k = 0; k < cfg_.max_tries && !placed; ++k) {
    // The centre is put on the plane itself: it is crossing it now, with W_x > 0.
    double y = rng_.uniform(cfg_.y_min, cfg_.y_max);
    if (s.grid.periodic_y() && y >= s.grid.ly()) y -= s.grid.ly();
    if (spot_is_free(s, cfg_.x, y)) {
      d.r = {cfg_.x, y};
      s.add_disk(d);
      ++injected_;
      placed = true;
    } else {
      ++blocked_tries_;
    }
  }
  if (!placed) ++skipped_;
  next_ -= std::log(rng_.uniform_pos()) / rate_;
}

void StreamInletPlane::cells(const CellGrid& grid, std::vector<int>& out) const { plane_cells(grid, x_, out); }

double StreamInletPlane::event_time(const SystemState&, int, const DiskNow& d) const {
  // A disk found behind the plane (round-off) while moving back leaves at once.
  return d.vx < 0.0 ? std::max(0.0, (x_ - d.x) / d.vx) : kNever;
}

void StreamInletPlane::action(SystemState& s, int i) {
  s.remove_disk(i);
  ++removed_;
}

// Its random stream, the next arrival time and the counters; the rate is configuration.
void StreamInlet::save(io::ArchiveWriter& w) const {
  w.rng(rng_);
  w.pod(next_);
  w.pod(arrivals_);
  w.pod(injected_);
  w.pod(blocked_tries_);
  w.pod(skipped_);
}

void StreamInlet::load(io::ArchiveReader& r) {
  r.rng(rng_);
  r.pod(next_);
  r.pod(arrivals_);
  r.pod(injected_);
  r.pod(blocked_tries_);
  r.pod(skipped_);
}

// The count of disks it removed; the plane is configuration.
void StreamInletPlane::save(io::ArchiveWriter& w) const { w.pod(removed_); }

void StreamInletPlane::load(io::ArchiveReader& r) { r.pod(removed_); }

}  // namespace grainflow::ed
