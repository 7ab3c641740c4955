// The box walls' surface and motion ([boundary.walls]): slip (specular, restitution r),
// no-slip by thermal re-emission at the wall temperature, or no-slip by tangential flip,
// in each wall's frame; the walls at y = 0 and y = Ly may move along x at U = [U_low,
// U_high] (planar Couette flow, seed 003 §4.2). Whenever the box has walls in y, stats.csv
// gets each y wall's shear force, pressure and power per unit length (the shear stress
// that, with the velocity profile, gives the viscosity: studies/couette.hpp).
#include <memory>

#include "engine/core/rng.hpp"
#include "engine/ed/elastic_walls.hpp"
#include "engine/ed/simulation.hpp"
#include "engine/io/archive.hpp"
#include "scenes/src/engines/ed/ed_agents.hpp"
#include "scenes/src/engines/ed/ed_keys.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/scene/toml_text.hpp"

namespace grainflow::scenes {
namespace {

using namespace ed_keys;

void declare_keys(Schema& s) {
  auto& w = s.optional_table(walls, "surface and motion of the box walls on the non-periodic axes (§3.1, §4.2: planar "
                                    "Couette flow between walls in y moving along x)");
  w.add_enum(walls_kind, {"slip", "noslip_thermal", "noslip_flip"}, "slip",
             "surface, in the wall's frame: specular slip (restitution r; exerts no shear), no-slip by thermal "
             "re-emission at kT (the walls take up the heat of shear), or no-slip by a random flip of the tangential "
             "velocity (restitution r; conserves energy in the wall frame when r = 1)");
  w.add_float(walls_r, 1.0, "normal restitution of the walls (slip, noslip_flip); default 1 (elastic)")
      .at_least(0.0)
      .at_most(1.0)
      .optional();
  w.add_float(walls_kT, 0.02, "wall temperature (noslip_thermal); default system.kT", "m σ²/τ²").above(0.0).optional();
  w.add_float_array(walls_U, {0.0, 0.0}, {"U_low", "U_high"},
                    "x velocities of the walls at y = 0 and y = Ly (Couette: [−U/2, U/2]); the walls in x are at rest",
                    "σ/τ");

  s.add_check([](const Scene& sc, SceneCheck& c) {
    if (!sc.has(walls)) return;
    const auto axes = sc.get(periodic);
    const bool open_x = sc.get(stream_kind) != "periodic";
    const bool walls_y = !axes[1], walls_x = !axes[0] && !open_x;
    if (!walls_x && !walls_y) {
      c.fail(walls_kind.path, "[boundary.walls] describes walls the box does not have; allowed: with a non-periodic "
                              "axis (boundary.periodic = [true, false] for walls in y)");
      return;
    }
    const auto U = sc.get(walls_U);
    if (!walls_y && (U[0] != 0.0 || U[1] != 0.0))
      c.fail(walls_U.path, "boundary.walls.U = [" + toml_float(U[0]) + ", " + toml_float(U[1]) +
                               "] moves walls in y, which the box does not have; allowed: [0.0, 0.0], or "
                               "boundary.periodic = [true, false]");
    const std::string kind = sc.get(walls_kind);
    if (kind == "noslip_thermal" && sc.has(walls_r))
      c.fail(walls_r.path, "boundary.walls.r is not used by kind = \"noslip_thermal\" (re-emission draws the normal "
                           "speed); allowed: r with \"slip\" or \"noslip_flip\"");
    if (kind != "noslip_thermal" && sc.has(walls_kT))
      c.fail(walls_kT.path, "boundary.walls.kT is used only by kind = \"noslip_thermal\" (kind = \"" + kind + "\")");
  });
}

// The y walls' books over a stats window: x force, pressure and power per unit length.
class WallsRun final : public EdAgentRun {
public:
  WallsRun(const ed::ElasticWalls& w, double lx) : walls_(w), lx_(lx) { mark(); }
  std::vector<StatsColumn> stats_columns() const override {
    constexpr const char* stress = "E/σ²";  // force per unit wall length
    const std::string per = " per unit time and unit wall length over the stats window (Σ impulses / (window × Lx))";
    return {{"wall_fx_low", stress,
             "x force the wall at y = 0 exerts on the gas" + per + ": −σ_xy, the shear stress it transmits"},
            {"wall_fx_high", stress,
             "x force the wall at y = Ly exerts on the gas" + per + ": +σ_xy, the shear stress it transmits"},
            {"wall_pressure_low", stress, "normal force the gas exerts on the wall at y = 0" + per},
            {"wall_pressure_high", stress, "normal force the gas exerts on the wall at y = Ly" + per},
            {"wall_power_low", "E/(τ·σ)",
             "kinetic energy the wall at y = 0 gives the gas per unit time and unit wall length over the stats "
             "window (negative: heat removed)"},
            {"wall_power_high", "E/(τ·σ)",
             "kinetic energy the wall at y = Ly gives the gas per unit time and unit wall length over the stats "
             "window (negative: heat removed)"}};
  }
  void stats_row(double duration, std::vector<double>& row) override {
    // Per unit time and unit wall length: wall_fx_* is the x force the wall exerts on the
    // gas (the shear stress it transmits: −σ_xy at y = 0, +σ_xy at y = Ly), the pressure
    // the normal force the gas exerts on it, the power the energy it gives the gas.
    const double per = duration > 0 ? 1.0 / (duration * lx_) : 0.0;
    const Vec2 dl = walls_.momentum_given(ed::wall_y_low) - p_low_;
    const Vec2 dh = walls_.momentum_given(ed::wall_y_high) - p_high_;
    row.push_back(dl.x() * per);
    row.push_back(dh.x() * per);
    row.push_back(dl.y() * per);
    row.push_back(-dh.y() * per);
    row.push_back((walls_.energy_given(ed::wall_y_low) - e_low_) * per);
    row.push_back((walls_.energy_given(ed::wall_y_high) - e_high_) * per);
    if (duration > 0) mark();
  }
  void figures(std::vector<std::pair<std::string, double>>& out) const override {
    out.emplace_back("wall_hits_low", double(walls_.hits(ed::wall_y_low)));
    out.emplace_back("wall_hits_high", double(walls_.hits(ed::wall_y_high)));
  }
  // The stats window's start (the walls' books themselves are in the engine's state).
  void save(io::ArchiveWriter& w) const override {
    w.tag("walls.run");
    for (const Vec2& p : {p_low_, p_high_}) {
      w.pod(p.x());
      w.pod(p.y());
    }
    w.pod(e_low_);
    w.pod(e_high_);
  }
  void load(io::ArchiveReader& r) override {
    r.tag("walls.run");
    for (Vec2* p : {&p_low_, &p_high_}) {
      const double x = r.get<double>();
      *p = Vec2(x, r.get<double>());
    }
    r.pod(e_low_);
    r.pod(e_high_);
  }

private:
  void mark() {
    p_low_ = walls_.momentum_given(ed::wall_y_low);
    p_high_ = walls_.momentum_given(ed::wall_y_high);
    e_low_ = walls_.energy_given(ed::wall_y_low);
    e_high_ = walls_.energy_given(ed::wall_y_high);
  }
  const ed::ElasticWalls& walls_;  // owned by the simulation
  double lx_;
  Vec2 p_low_ = Vec2::Zero(), p_high_ = Vec2::Zero();
  double e_low_ = 0.0, e_high_ = 0.0;
};

std::unique_ptr<EdAgentRun> attach(const Scene& sc, ed::Simulation& sim) {
  ed::ElasticWalls* w = sim.walls();
  if (!w) return nullptr;  // validation refused [boundary.walls] without walls
  if (sc.has(walls)) {
    ed::WallConfig wc;
    const std::string kind = sc.get(walls_kind);
    wc.surface = kind == "noslip_thermal" ? ed::WallSurface::thermal
                 : kind == "noslip_flip"  ? ed::WallSurface::flip
                                          : ed::WallSurface::slip;
    wc.restitution = sc.find(walls_r).value_or(1.0);
    wc.kT = sc.find(walls_kT).value_or(sim.config().kT);
    const auto U = sc.get(walls_U);
    wc.u_low = U[0];
    wc.u_high = U[1];
    wc.seed = core::substream_seed(sim.config().seed, 4);  // its own random stream
    w->configure(wc);
  }
  if (!w->walls_y()) return nullptr;
  return std::make_unique<WallsRun>(*w, sim.config().lx);
}

}  // namespace

EdAgentEntry walls_agent() {
  return {"walls", "box walls: slip, thermal or flip surface, walls in y moving along x (§3.1, §4.2)", &declare_keys,
          &attach};
}

}  // namespace grainflow::scenes
