// The high-density outlet of seed 003 §3.3 (Fig. 3.8): a "filter" plane x_f a few radii
// before the outlet x = Lx. A disk crossing it in +x is turned back with the low-density
// outlet's probability F−/F+ and a velocity from the back-flux distribution (Eq. 3.15–3.18,
// 3.28), or frozen: infinitely heavy at the stream velocity, removed when it reaches Lx.
// The back flux is that of a stream at U and a temperature: the stream's kT (seed), or the
// temperature of the disks now arriving (local_kT), for a stream that cools on its way
// (inelastic disks, seed ch. 5) and whose real continuation beyond the outlet is as cold.
#pragma once
#include <cstdint>
#include <memory>

#include "engine/core/rng.hpp"
#include "engine/ed/arrival_temperature.hpp"
#include "engine/ed/event_source.hpp"
#include "engine/ed/stream_flux.hpp"

namespace grainflow::ed {

struct FilterConfig {
  double lx = 0.0;               // the real outlet boundary x = Lx
  double distance = 3.0;         // x_f = Lx − distance; more than a radius (seed §3.3)
  double U = 0.0, kT = 0.02, mass = 1.0;  // the stream
  // Delete the disks that are not turned back instead of freezing them: the low-density
  // outlet, which leaks at high area fraction (seed Fig. 3.7). For comparison only.
  bool delete_instead_of_freeze = false;
  // Take the back flux at the arriving disks' temperature (ArrivalTemperature over the last
  // `window` disks reaching the plane, starting from kT); the flux tables are rebuilt when
  // it has moved by more than 2 %.
  bool local_kT = false;
  double window = 100.0;
  std::uint64_t seed = 1;
};

class StreamFilter final : public ParticleAgent {
public:
  // Throws grainflow::Error for a distance outside (0, Lx) or a stream StreamFlux rejects.
  explicit StreamFilter(const FilterConfig& cfg);
  std::string_view name() const override { return "stream filter"; }
  void cells(const CellGrid& grid, std::vector<int>& out) const override;
  double event_time(const SystemState& state, int i, const DiskNow& d) const override;
  void action(SystemState& state, int i) override;
  void save(io::ArchiveWriter& w) const override;
  void load(io::ArchiveReader& r) override;

  double plane() const { return xf_; }
  double turn_back_probability() const { return flux_.turn_back_probability(); }
  double kT() const { return flux_.kT(); }  // the temperature of the back flux now
  std::uint64_t turned_back() const { return turned_; }
  std::uint64_t frozen() const { return frozen_; }

private:
  FilterConfig cfg_;
  double xf_;
  StreamFlux flux_;
  core::Rng rng_;
  std::uint64_t turned_ = 0, frozen_ = 0;
  ArrivalTemperature arrivals_;  // local_kT
};

}  // namespace grainflow::ed
