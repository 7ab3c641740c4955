#include "scenes/src/scene/run_keys.hpp"

#include "scenes/src/scene/scene.hpp"

namespace grainflow::scenes::run_keys {

void declare(Schema& s, std::span<const std::string> engine_names) {
  auto& run = s.section("run", "what to run and for how long");
  run.add_enum(engine, {engine_names.begin(), engine_names.end()}, "",
               "which engine runs the scene: 2D event-driven disks or 3D DEM spheres")
      .required();
  run.add_float(until, 0.0, "simulated time to reach (ED: σ√(m/kT) units with σ = m = 1; DEM: seconds)",
                "time units")
      .above(0.0)
      .optional()
      .may_change_on_resume();
  run.add_int(steps, 0, "number of steps to run instead of `until` (DEM: integration steps; ED: events)")
      .at_least(1)
      .optional()
      .may_change_on_resume();
  run.add_int(seed, 1, "seed of the run's one random generator; same scene + seed ⇒ same numbers").at_least(0);
  run.add_string(title, "", "free text shown in labels and recorded in run.json");
  s.add_check([](const Scene& sc, SceneCheck& c) {
    if (sc.has(until.path) == sc.has(steps.path))
      c.fail(until.path, "give exactly one of run.until (simulated time) or run.steps");
  });
}

}  // namespace grainflow::scenes::run_keys
