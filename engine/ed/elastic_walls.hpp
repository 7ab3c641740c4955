// Flat box walls on the non-periodic sides of the domain (seed 003 §3.1–3.3): a disk
// touching a wall has its normal velocity reversed and scaled by the wall restitution
// (1 = elastic). One ParticleAgent serves all walls; it lives in the boundary cells.
#pragma once
#include "engine/ed/event_source.hpp"

namespace grainflow::ed {

class ElasticWalls final : public ParticleAgent {
public:
  // walls_x: walls at x = 0 and x = Lx; walls_y: at y = 0 and y = Ly.
  ElasticWalls(double lx, double ly, bool walls_x, bool walls_y, double restitution = 1.0);
  std::string_view name() const override { return "walls"; }
  void cells(const CellGrid& grid, std::vector<int>& out) const override;
  double event_time(const SystemState& state, int i) const override;
  void action(SystemState& state, int i) override;
  void save(io::ArchiveWriter& w) const override;
  void load(io::ArchiveReader& r) override;

  // Momentum given to the walls so far (Σ of −Δp of the disks), for wall pressure.
  double impulse_x() const { return impulse_x_; }
  double impulse_y() const { return impulse_y_; }

private:
  double lx_, ly_;
  bool wx_, wy_;
  double r_;
  double impulse_x_ = 0.0, impulse_y_ = 0.0;
};

}  // namespace grainflow::ed
