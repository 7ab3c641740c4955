// The low-density outlet of an open stream along +x (seed 003 §3.2, §3.3): a disk whose
// centre reaches x = x_out moving in +x is turned back with probability F−/F+ (Eq. 3.15,
// 3.17), with a fresh velocity from the backward flux distribution (Eq. 3.28), or leaves.
#pragma once
#include <cstdint>
#include <memory>

#include "engine/core/rng.hpp"
#include "engine/ed/event_source.hpp"
#include "engine/ed/stream_flux.hpp"

namespace grainflow::ed {

struct StreamOutletConfig {
  double x = 1.0;          // the outlet plane x_out (≤ box length − disk radius)
  // false: every arriving disk leaves — the seed's high-Mach simplification (§3.2), which
  // starves a slower stream of its back flux F−; kept to show why turning back is needed.
  bool turn_back = true;
  std::uint64_t seed = 2;  // the outlet's own random stream
};

// Only the disks in the cells that contain the plane are asked. A frozen disk (the dense
// outlet filter, Fig. 3.8) reaching the plane always leaves.
class StreamOutlet final : public ParticleAgent {
public:
  StreamOutlet(const StreamOutletConfig& cfg, std::shared_ptr<const StreamFlux> flux);
  std::string_view name() const override { return "stream_outlet"; }
  void cells(const CellGrid& grid, std::vector<int>& out) const override;
  double event_time(const SystemState& state, int i, const DiskNow& d) const override;
  void action(SystemState& state, int i) override;
  void save(io::ArchiveWriter& w) const override;
  void load(io::ArchiveReader& r) override;

  const StreamOutletConfig& config() const { return cfg_; }
  double turn_back_probability() const { return cfg_.turn_back ? flux_->turn_back_probability() : 0.0; }
  std::uint64_t arrivals() const { return arrivals_; }
  std::uint64_t turned_back() const { return turned_; }
  std::uint64_t removed() const { return removed_; }

private:
  StreamOutletConfig cfg_;
  std::shared_ptr<const StreamFlux> flux_;
  core::Rng rng_;
  std::uint64_t arrivals_ = 0, turned_ = 0, removed_ = 0;
};

}  // namespace grainflow::ed
