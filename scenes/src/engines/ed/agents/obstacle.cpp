// The fixed circular obstacle of seed 003 §3.3 and ch. 5 ([boundary.obstacle]): slip,
// or no-slip by thermal re-emission or tangential flip. Draws itself, masks the bins it
// covers, and reports the drag it receives (Fig. 4.19) in stats.csv.
#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>

#include "engine/core/rng.hpp"
#include "engine/io/archive.hpp"
#include "engine/ed/circular_obstacle.hpp"
#include "engine/ed/simulation.hpp"
#include "scenes/src/engines/ed/ed_agents.hpp"
#include "scenes/src/engines/ed/ed_keys.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/scene/toml_text.hpp"

namespace grainflow::scenes {
namespace {

using namespace ed_keys;

void declare_keys(Schema& s) {
  auto& obs = s.optional_table(obstacle, "fixed circular obstacle (§3.3, §5)");
  obs.add_float(obstacle_D, 74.0, "obstacle diameter", "σ").above(0.0);
  obs.add_float(obstacle_x, 0.0, "obstacle centre x (box origin at the lower left corner)", "σ").required();
  obs.add_float(obstacle_y, 0.0, "obstacle centre y", "σ").required();
  obs.add_enum(obstacle_kind, {"slip", "noslip_thermal", "noslip_flip"}, "slip",
               "surface: specular slip, no-slip by thermal re-emission, or no-slip by tangential flip");
  obs.add_float(obstacle_r, 1.0, "restitution of the obstacle surface (slip, noslip_flip; the thermal surface "
                                 "re-emits and has none); default 1 (elastic)")
      .above(0.0)
      .at_most(1.0)
      .optional();

  s.add_check([](const Scene& sc, SceneCheck& c) {
    if (!sc.has(obstacle)) return;
    const auto L = sc.get(box);
    const double R = sc.get(obstacle_D) / 2;
    const double x = sc.get(obstacle_x), y = sc.get(obstacle_y);
    if (x - R < 0 || x + R > L[0] || y - R < 0 || y + R > L[1])
      c.fail(obstacle_x.path, "obstacle of diameter " + toml_float(2 * R) + " at (" + toml_float(x) + ", " +
                                  toml_float(y) + ") does not fit in the box [" + toml_float(L[0]) + ", " +
                                  toml_float(L[1]) + "]; allowed: R ≤ x ≤ Lx − R, R ≤ y ≤ Ly − R");
    // A restitution no collision uses is a mistake in the scene (the user thinks the
    // thermal surface is inelastic), unless a phase switches to a surface that uses it.
    if (sc.has(obstacle_r) && !obstacle_r_used(sc, std::size_t(-1)))
      c.fail(obstacle_r.path, "boundary.obstacle.r = " + toml_float(sc.get(obstacle_r)) +
                                  " is not used by boundary.obstacle.kind = \"noslip_thermal\" (re-emission draws the "
                                  "normal speed); allowed: kind \"slip\" or \"noslip_flip\", or a [[phase]] "
                                  "obstacle_kind that switches to one of them");
  });
}

class ObstacleRun final : public EdAgentRun {
public:
  explicit ObstacleRun(ed::CircularObstacle& o) : obstacle_(o) {}
  void draw(render::Snapshot& s) const override {
    s.obstacles.push_back({obstacle_.config().centre, obstacle_.config().radius});
  }
  bool solid(const Vec2& p) const override {
    return (p - obstacle_.config().centre).norm() < obstacle_.config().radius;
  }
  std::vector<StatsColumn> stats_columns() const override {
    constexpr const char* force = "E/σ";
    return {{"drag_x", force,
             "x component of the drag on the obstacle: the momentum the disks gave it per unit time over the stats "
             "window (Σ impulses / window length); the whole force, not per unit diameter (divide by "
             "boundary.obstacle.D for that)"},
            {"drag_y", force, "y component of the drag on the obstacle, as drag_x (the lift)"}};
  }
  void stats_row(double duration, std::vector<double>& row) override {
    // Drag: momentum the obstacle received per unit time over the window (Fig. 4.19).
    Vec2 drag = Vec2::Zero();
    if (duration > 0) {
      drag = (obstacle_.impulse() - impulse_at_reset_) / duration;
      impulse_at_reset_ = obstacle_.impulse();
    }
    row.push_back(drag.x());
    row.push_back(drag.y());
  }
  void figures(std::vector<std::pair<std::string, double>>& out) const override {
    out.emplace_back("obstacle_hits", double(obstacle_.hits()));
  }
  // The drag window's start (the obstacle's impulse itself is in the engine's state).
  void save(io::ArchiveWriter& w) const override {
    w.tag("obstacle.run");
    w.pod(impulse_at_reset_.x());
    w.pod(impulse_at_reset_.y());
  }
  void load(io::ArchiveReader& r) override {
    r.tag("obstacle.run");
    const double x = r.get<double>();
    impulse_at_reset_ = Vec2(x, r.get<double>());
  }

private:
  ed::CircularObstacle& obstacle_;  // owned by the simulation
  Vec2 impulse_at_reset_ = Vec2::Zero();
};

std::unique_ptr<EdAgentRun> attach(const Scene& sc, ed::Simulation& sim) {
  if (!sc.has(obstacle)) return nullptr;
  ed::ObstacleConfig oc;
  oc.centre = {sc.get(obstacle_x), sc.get(obstacle_y)};
  oc.radius = sc.get(obstacle_D) / 2;
  oc.boundary = obstacle_boundary(sc.get(obstacle_kind));
  oc.restitution = sc.find(obstacle_r).value_or(1.0);
  oc.kT = sim.config().kT;  // boundary temperature of the thermal wall [TTKB98]
  oc.seed = core::substream_seed(sim.config().seed, 1);  // its own random stream
  return std::make_unique<ObstacleRun>(sim.add_obstacle(oc));
}

}  // namespace

ed::ObstacleBoundary obstacle_boundary(std::string_view kind) {
  if (kind == "slip") return ed::ObstacleBoundary::slip;
  if (kind == "noslip_thermal") return ed::ObstacleBoundary::thermal;
  if (kind == "noslip_flip") return ed::ObstacleBoundary::flip;
  throw std::logic_error("obstacle_boundary: '" + std::string(kind) + "' (validation allows only the three)");
}

std::string_view obstacle_kind_name(ed::ObstacleBoundary b) {
  switch (b) {
    case ed::ObstacleBoundary::slip: return "slip";
    case ed::ObstacleBoundary::thermal: return "noslip_thermal";
    case ed::ObstacleBoundary::flip: return "noslip_flip";
  }
  return "?";
}

EdAgentEntry obstacle_agent() {
  return {"obstacle", "fixed circular obstacle, slip or no-slip (§3.3, ch. 5)", &declare_keys, &attach};
}

}  // namespace grainflow::scenes
