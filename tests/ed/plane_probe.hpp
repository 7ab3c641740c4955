// A test probe for the ED engine: an agent that records every disk centre reaching the
// plane x = xm, either way, without touching the disk (the open-stream tests' mid-channel
// crossings, the event loop's held agent events).
#pragma once
#include <cmath>
#include <string_view>
#include <vector>

#include "engine/ed/simulation.hpp"
#include "engine/ed/stream_inlet.hpp"
#include "engine/io/archive.hpp"

namespace grainflow::test {

// Records the time and W_x of each arrival while `recording`. A disk within 1e−9 of the
// plane is not asked again, so the one just recorded (left on the plane by the
// synchronisation) is not recorded twice.
class PlaneProbe final : public ed::ParticleAgent {
public:
  explicit PlaneProbe(double xm) : xm_(xm) {}
  std::string_view name() const override { return "test_plane"; }
  void cells(const ed::CellGrid& grid, std::vector<int>& out) const override { ed::plane_cells(grid, xm_, out); }
  double event_time(const ed::SystemState&, int, const ed::DiskNow& d) const override {
    const double dx = xm_ - d.x;
    if (std::abs(dx) < 1e-9 || dx * d.vx <= 0.0) return ed::kNever;
    return dx / d.vx;
  }
  void action(ed::SystemState& s, int i) override {
    if (!recording) return;
    times.push_back(s.now());
    wx.push_back(s.disk[i].vx);
  }
  // What it has recorded so far; the plane is configuration.
  void save(io::ArchiveWriter& w) const override {
    w.pod(recording);
    w.array(times);
    w.array(wx);
  }
  void load(io::ArchiveReader& r) override {
    r.pod(recording);
    r.array(times);
    r.array(wx);
  }
  bool recording = false;
  std::vector<double> times, wx;

private:
  double xm_;
};

}  // namespace grainflow::test
