// The fluid's measured transport numbers ([medium], seed 003 §4.2): the kinematic
// viscosity ν from planar Couette flow (the couette study) and the speed of sound c from a
// standing wave (the sound_speed study). They change no event; with a stream U past an
// obstacle of diameter D the frames' caption and run.json give the flow's Reynolds number
// Re = U D / ν and Mach number Ma = U / c, as the seed labels its figures (Figs. 4.2–4.7).
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "engine/io/archive.hpp"
#include "scenes/src/engines/ed/ed_agents.hpp"
#include "scenes/src/engines/ed/ed_keys.hpp"
#include "scenes/src/scene/scene.hpp"

namespace grainflow::scenes {
namespace {

using namespace ed_keys;

void declare_keys(Schema& s) {
  auto& m = s.optional_table(medium, "the fluid's measured transport numbers, for the flow's Reynolds and Mach numbers "
                                     "(seed 003 §4.2); they change no event");
  m.add_float(medium_nu, 0.65, "kinematic viscosity ν (the couette study); with a stream and an obstacle the caption and "
                               "run.json give Re = U D / ν",
              "σ²/τ")
      .above(0.0)
      .optional();
  m.add_float(medium_sound_speed, 1.4, "speed of sound c ([study] kind = \"sound_speed\"); with a stream the caption "
                                       "and run.json give Ma = U / c",
              "σ/τ")
      .above(0.0)
      .optional();
  s.add_check([](const Scene& sc, SceneCheck& c) {
    if (sc.has(medium) && !sc.has(medium_nu) && !sc.has(medium_sound_speed))
      c.fail(medium.path, "[medium] gives nothing; allowed: at least one of medium.nu, medium.sound_speed");
  });
}

// "%.3g": Re and Ma are estimates, to the digits ν and c carry.
std::string figure(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", x);
  return b;
}

class MediumRun final : public EdAgentRun {
public:
  MediumRun(std::optional<double> Re, std::optional<double> Ma) : Re_(Re), Ma_(Ma) {}
  void labels(std::vector<std::pair<std::string, std::string>>& out) const override {
    if (Re_) out.emplace_back("Re", figure(*Re_));
    if (Ma_) out.emplace_back("Ma", figure(*Ma_));
  }
  void figures(std::vector<std::pair<std::string, double>>& out) const override {
    if (Re_) out.emplace_back("Re", *Re_);
    if (Ma_) out.emplace_back("Ma", *Ma_);
  }
  // Nothing that changes: both numbers come from the scene.
  void save(io::ArchiveWriter& w) const override { w.tag("medium.run"); }
  void load(io::ArchiveReader& r) override { r.tag("medium.run"); }

private:
  std::optional<double> Re_, Ma_;
};

std::unique_ptr<EdAgentRun> attach(const Scene& sc, ed::Simulation&) {
  if (!sc.has(medium)) return nullptr;
  const std::optional<double> nu = sc.find(medium_nu), c = sc.find(medium_sound_speed);
  // The stream speed U (system.U, along +x); Re needs the obstacle's diameter as well.
  const double U = std::abs(sc.get(ed_keys::U));
  std::optional<double> Re, Ma;
  if (U > 0 && nu && sc.has(obstacle)) Re = U * sc.get(obstacle_D) / *nu;
  if (U > 0 && c) Ma = U / *c;
  return std::make_unique<MediumRun>(Re, Ma);
}

}  // namespace

EdAgentEntry medium_agent() {
  return {"medium", "the fluid's viscosity and speed of sound, for Re = U D / ν and Ma = U / c (§4.2)", &declare_keys,
          &attach};
}

}  // namespace grainflow::scenes
