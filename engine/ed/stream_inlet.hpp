// The low-density inlet of an open stream along +x (seed 003 §3.2): disks enter at the
// plane x = x_in as a Poisson stream at the rate n·F+·L with velocities drawn from the
// forward flux distribution (Eq. 3.29), and disks crossing the plane backwards leave.
#pragma once
#include <cstdint>
#include <memory>

#include "engine/core/rng.hpp"
#include "engine/ed/event_source.hpp"
#include "engine/ed/stream_flux.hpp"

namespace grainflow::ed {

struct StreamInletConfig {
  double x = 1.0;                    // the inlet plane x_in (≥ the disk radius)
  double y_min = 0.0, y_max = 1.0;   // centres enter at y uniform in [y_min, y_max): L = y_max − y_min
  double number_density = 0.05;      // n of the stream, disks per unit area (η = n π σ²/4)
  double radius = 0.5;               // of the entering disks (their mass is the flux's m)
  int max_tries = 20;                // random spots tried per arrival before it is skipped
  std::uint64_t seed = 1;            // the inlet's own random stream
  double t_start = 0.0;              // arrivals are drawn from this time on
};

// The injector: a timer whose events are the Poisson arrival times. Each arrival draws a
// velocity (sample_forward) and tries up to max_tries random spots on the plane until the
// new disk overlaps no other (the seed's "try several random positions", §3.2); an arrival
// that finds no spot is skipped and counted — at low density this is rare.
class StreamInlet final : public TimerAgent {
public:
  // Throws grainflow::Error for an empty plane, n ≤ 0, radius ≤ 0 or max_tries < 1.
  StreamInlet(const StreamInletConfig& cfg, std::shared_ptr<const StreamFlux> flux);
  std::string_view name() const override { return "stream_inlet"; }
  double event_time(const SystemState&) const override { return next_; }
  void action(SystemState& state) override;
  void save(io::ArchiveWriter& w) const override;
  void load(io::ArchiveReader& r) override;

  const StreamInletConfig& config() const { return cfg_; }
  double rate() const { return rate_; }  // n F+ L, arrivals per unit time
  std::uint64_t arrivals() const { return arrivals_; }
  std::uint64_t injected() const { return injected_; }
  std::uint64_t blocked_tries() const { return blocked_tries_; }  // spots found occupied
  std::uint64_t skipped() const { return skipped_; }              // arrivals with no free spot

private:
  bool spot_is_free(const SystemState& s, double x, double y) const;

  StreamInletConfig cfg_;
  std::shared_ptr<const StreamFlux> flux_;
  core::Rng rng_;
  double rate_, next_;
  std::uint64_t arrivals_ = 0, injected_ = 0, blocked_tries_ = 0, skipped_ = 0;
};

// The inlet plane as seen by the disks: one moving in −x whose centre reaches x_in leaves
// the system (the stream's own back flux F− through the plane, Eq. 3.15). Only the disks in
// the cells that contain the plane are asked.
class StreamInletPlane final : public ParticleAgent {
public:
  explicit StreamInletPlane(double x) : x_(x) {}
  std::string_view name() const override { return "stream_inlet_plane"; }
  void cells(const CellGrid& grid, std::vector<int>& out) const override;
  double event_time(const SystemState& state, int i, const DiskNow& d) const override;
  void action(SystemState& state, int i) override;
  void save(io::ArchiveWriter& w) const override;
  void load(io::ArchiveReader& r) override;

  double x() const { return x_; }
  std::uint64_t removed() const { return removed_; }

private:
  double x_;
  std::uint64_t removed_ = 0;
};

// Cells of the grid columns that contain the plane x = const (both neighbours when it lies
// on a column boundary): the only disks that can reach it before a cell crossing.
void plane_cells(const CellGrid& grid, double x, std::vector<int>& out);

}  // namespace grainflow::ed
