// Flat box walls on the non-periodic sides of the domain (seed 003 §3.1–3.3, §4.2, ch. 6):
// one ParticleAgent serves all walls; it lives in the boundary cells. The walls at y = 0
// and y = Ly may move along x (planar Couette flow, seed 003 §4.2: the viscosity estimate);
// the walls at x = 0 and x = Lx are at rest. Every wall has the same surface, applied in
// the wall's own frame (velocities relative to the wall):
//   slip     specular: the normal velocity reversed and scaled by the restitution r (1 =
//            elastic); the tangential one kept — a moving slip wall exerts no shear;
//   thermal  diffuse re-emission at the wall temperature kT_w [TTKB98]: the normal speed
//            from the flux (Rayleigh) distribution, the tangential velocity Gaussian, both
//            at kT_w, around the wall's velocity (thermal_reemission, as the thermal
//            obstacle); the walls then take up the heat of viscous shear;
//   flip     the normal velocity reversed and scaled by r, the sign of the tangential
//            velocity relative to the wall flipped with probability 1/2 (the seed's
//            no-slip without thermal excitation, ch. 5), energy-conserving in the wall frame.
// Every wall keeps the momentum and energy it gave the disks (for the wall shear stress,
// pressure and heat flux).
#pragma once
#include <array>
#include <cstdint>
#include <string_view>

#include "engine/core/rng.hpp"
#include "engine/core/vec.hpp"
#include "engine/ed/event_source.hpp"

namespace grainflow::ed {

enum class WallSurface { slip, thermal, flip };
std::string_view wall_surface_name(WallSurface s);

struct WallConfig {
  WallSurface surface = WallSurface::slip;
  double restitution = 1.0;          // normal restitution r (slip, flip), [0, 1]
  double kT = 0.02;                  // wall temperature (thermal), > 0
  double u_low = 0.0, u_high = 0.0;  // x velocity of the walls at y = 0 and at y = Ly
  std::uint64_t seed = 1;            // the walls' random stream (thermal, flip)
};

// The four walls, in the order the books keep them.
enum WallId : int { wall_x_low = 0, wall_x_high = 1, wall_y_low = 2, wall_y_high = 3 };

class ElasticWalls final : public ParticleAgent {
public:
  // walls_x: walls at x = 0 and x = Lx; walls_y: at y = 0 and y = Ly. Slip, at rest.
  ElasticWalls(double lx, double ly, bool walls_x, bool walls_y, double restitution = 1.0);
  // Another surface or wall velocity, before the first event (it changes no prediction:
  // a wall's time depends only on the normal motion). Throws grainflow::Error for values
  // out of range.
  void configure(const WallConfig& cfg);
  std::string_view name() const override { return "walls"; }
  void cells(const CellGrid& grid, std::vector<int>& out) const override;
  double event_time(const SystemState& state, int i, const DiskNow& d) const override;
  void action(SystemState& state, int i) override;
  void save(io::ArchiveWriter& w) const override;
  void load(io::ArchiveReader& r) override;

  const WallConfig& config() const { return cfg_; }
  bool walls_x() const { return wx_; }
  bool walls_y() const { return wy_; }
  // Momentum given to the walls so far (Σ of −Δp of the disks), for wall pressure.
  double impulse_x() const { return impulse_x_; }
  double impulse_y() const { return impulse_y_; }
  // Of one wall since the start: the momentum it gave the disks (Σ Δp of the disks it
  // met), the kinetic energy it gave them (Σ Δ(m v²/2)), and its hits.
  Vec2 momentum_given(WallId w) const { return given_p_[w]; }
  double energy_given(WallId w) const { return given_e_[w]; }
  std::uint64_t hits(WallId w) const { return hits_[w]; }

private:
  double lx_, ly_;
  bool wx_, wy_;
  WallConfig cfg_;
  core::Rng rng_;
  double impulse_x_ = 0.0, impulse_y_ = 0.0;
  std::array<Vec2, 4> given_p_{Vec2::Zero(), Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};
  std::array<double, 4> given_e_{0.0, 0.0, 0.0, 0.0};
  std::array<std::uint64_t, 4> hits_{0, 0, 0, 0};
};

}  // namespace grainflow::ed
