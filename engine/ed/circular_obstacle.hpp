// A fixed circular obstacle in the stream (seed 003 §4.1, §5): disks bounce off it with
// slip (specular, normal restitution r), or no-slip in the two variants of the seed —
// thermal re-emission at the boundary temperature [TTKB98], or a random flip of the sign
// of the tangential velocity (with the normal one reversed and scaled by r). It records
// the momentum it receives, so the drag force is Δp/Δt (Fig. 4.19).
#pragma once
#include <cstdint>

#include "engine/core/rng.hpp"
#include "engine/core/vec.hpp"
#include "engine/ed/event_source.hpp"

namespace grainflow::ed {

enum class ObstacleBoundary { slip, thermal, flip };

struct ObstacleConfig {
  Vec2 centre{0.0, 0.0};
  double radius = 1.0;      // D/2 (seed: D = 74)
  ObstacleBoundary boundary = ObstacleBoundary::slip;
  double restitution = 1.0;  // r for slip and flip
  double kT = 0.02;          // boundary temperature for thermal re-emission
  std::uint64_t seed = 1;    // its own random stream (thermal and flip)
};

class CircularObstacle final : public ParticleAgent {
public:
  explicit CircularObstacle(const ObstacleConfig& cfg);
  std::string_view name() const override { return "obstacle"; }
  void cells(const CellGrid& grid, std::vector<int>& out) const override;
  double event_time(const SystemState& state, int i, const DiskNow& d) const override;
  void action(SystemState& state, int i) override;
  void save(io::ArchiveWriter& w) const override;
  void load(io::ArchiveReader& r) override;

  const ObstacleConfig& config() const { return cfg_; }
  // The surface's restitution from now on (phased runs; [0, 1], else grainflow::Error).
  // No prediction depends on it. A checkpoint keeps it.
  void set_restitution(double r);
  // The surface from now on (phased runs: the seed's dune run switches from thermal
  // re-emission to the tangential flip). No prediction depends on it; a checkpoint keeps it.
  void set_boundary(ObstacleBoundary b) { cfg_.boundary = b; }
  // Total momentum received from the disks since construction (drag = its rate).
  Vec2 impulse() const { return impulse_; }
  std::uint64_t hits() const { return hits_; }

private:
  ObstacleConfig cfg_;
  core::Rng rng_;
  Vec2 impulse_{0.0, 0.0};
  std::uint64_t hits_ = 0;
};

}  // namespace grainflow::ed
