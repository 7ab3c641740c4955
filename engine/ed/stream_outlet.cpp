#include "engine/ed/stream_outlet.hpp"

#include <algorithm>

#include "engine/core/error.hpp"
#include "engine/ed/stream_inlet.hpp"
#include "engine/ed/checkpoint.hpp"
#include "engine/ed/system_state.hpp"

namespace grainflow::ed {

StreamOutlet::StreamOutlet(const StreamOutletConfig& cfg, std::shared_ptr<const StreamFlux> flux)
    : cfg_(cfg), flux_(std::move(flux)), rng_(cfg.seed) {
  if (!flux_) throw Error("stream outlet: no flux distribution given");
}

void StreamOutlet::cells(const CellGrid& grid, std::vector<int>& out) const { plane_cells(grid, cfg_.x, out); }

double StreamOutlet::event_time(const SystemState&, int, const DiskNow& d) const {
  // Only +x motion meets the outlet, so a disk just turned back (W_x < 0) is not asked
  // again until a collision sends it forward; one found past the plane acts at once.
  return d.vx > 0.0 ? std::max(0.0, (cfg_.x - d.x) / d.vx) : kNever;
}

void StreamOutlet::action(SystemState& s, int i) {
  ++arrivals_;
  if (!s.frozen(i) && rng_.uniform() < turn_back_probability()) {
    const Vec2 w = flux_->sample_backward(rng_);
    s.set_velocity(i, w.x(), w.y());
    ++turned_;
  } else {
    s.remove_disk(i);
    ++removed_;
  }
}

// Its random stream and counters; the plane and the shared flux are configuration.
void StreamOutlet::save(io::ArchiveWriter& w) const {
  w.rng(rng_);
  w.pod(arrivals_);
  w.pod(turned_);
  w.pod(removed_);
}

void StreamOutlet::load(io::ArchiveReader& r) {
  r.rng(rng_);
  r.pod(arrivals_);
  r.pod(turned_);
  r.pod(removed_);
}

}  // namespace grainflow::ed
