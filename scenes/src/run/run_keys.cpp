// Schema of the sections every scene has whatever the engine: [run], [sample], [render],
// [output] (SPEC.md §3, §3b). Engine-specific keys live in scene_schema_ed/dem.cpp.
#include <array>
#include <cstdint>
#include <string>

#include "scenes/src/scene/scene.hpp"
#include "scenes/src/engines/engine_table.hpp"
#include "scenes/src/scene/schema.hpp"
#include "scenes/src/scene/toml_text.hpp"

namespace grainflow::scenes {

namespace {

std::vector<std::string> engine_names() {
  std::vector<std::string> names;
  for (const auto& e : engines()) names.emplace_back(e.name);
  return names;
}

bool is_hex_colour(const std::string& s) {
  if (s.size() != 7 && s.size() != 9) return false;
  if (s[0] != '#') return false;
  for (std::size_t i = 1; i < s.size(); ++i)
    if (!std::isxdigit(static_cast<unsigned char>(s[i]))) return false;
  return true;
}

}  // namespace

void add_common_schema(Schema& s) {
  auto& run = s.section("run", "what to run and for how long");
  run.add_enum("engine", engine_names(), "", "which engine runs the scene: 2D event-driven disks or 3D DEM spheres")
      .required();
  run.add_float("until", 0.0, "simulated time to reach (ED: σ√(m/kT) units with σ = m = 1; DEM: seconds)",
                "time units")
      .above(0.0)
      .optional();
  run.add_int("steps", 0, "number of steps to run instead of `until` (DEM: integration steps; ED: events)")
      .at_least(1)
      .optional();
  run.add_int("seed", 1, "seed of the run's one random generator; same scene + seed ⇒ same numbers")
      .at_least(0);
  run.add_string("title", "", "free text shown in labels and recorded in run.json");
  s.add_check([](const Scene& sc, SceneCheck& c) {
    if (sc.has("run.until") == sc.has("run.steps"))
      c.fail("run.until", "give exactly one of run.until (simulated time) or run.steps");
  });

  auto& sample = s.section("sample", "binned measurement fields (seed 003 §4.1)");
  sample.add_float("exposure", 1.0, "exposure τ_E: time over which binned fields are averaged per frame",
                   "time units")
      .above(0.0);
  sample.add_int_array("bins", {60, 60}, {"nx", "ny"}, "number of bins of the measurement grid")
      .at_least(1)
      .at_most(4096);

  auto& render = s.section("render", "what each frame shows and how it is drawn");
  render.add_int_array("size", {1280, 720}, {"w", "h"}, "frame size", "pixels")
      .at_least(16)
      .at_most(8192)
      .with_note("odd sizes are padded to even for the H.264 MP4");
  render.add_int_array("layout", {1, 1}, {"cols", "rows"}, "panel grid of each frame").at_least(1).at_most(8);
  render
      .add_string_array("panels", {"particles", "density", "temperature", "speed", "streamlines", "velocity"},
                        {"particles"}, "panels, filled row by row into the layout")
      .length(1, 64);
  render.add_enum("colormap", {"viridis", "inferno", "magma", "turbo", "cool-warm"}, "viridis",
                  "colour map of scalar fields and of particles coloured by an attribute");
  render.add_enum("color_by", {"uniform", "speed", "vx", "vy", "vz", "spin", "group", "height"}, "speed",
                  "particle attribute mapped to colour in the particles panel");
  render.add_float_array("range", {0.0, 1.0}, {"lo", "hi"},
                         "colour range of render.color_by (same unit as the attribute); when absent it is "
                         "taken from the first frame and kept for the whole run")
      .optional();
  render.add_enum("backend", {"auto", "egl", "osmesa"}, "auto",
                  "off-screen GL: EGL (surfaceless/device), OSMesa, or auto = EGL then OSMesa");
  render.add_int("msaa", 4, "multisample anti-aliasing samples per pixel (0 = off)").at_least(0).at_most(16);
  render.add_string("background", "#ffffff", "background colour, \"#rrggbb\" or \"#rrggbbaa\"");
  s.add_check([](const Scene& sc, SceneCheck& c) {
    const auto layout = sc.get<std::array<int, 2>>("render.layout");
    const auto panels = sc.get<std::vector<std::string>>("render.panels");
    if (panels.size() > std::size_t(layout[0]) * std::size_t(layout[1]))
      c.fail("render.panels", std::to_string(panels.size()) + " panels do not fit render.layout = [" +
                                  std::to_string(layout[0]) + ", " + std::to_string(layout[1]) +
                                  "]; allowed: at most cols × rows = " + std::to_string(layout[0] * layout[1]) +
                                  " panels");
    if (auto r = sc.find<std::array<double, 2>>("render.range"); r && !((*r)[0] < (*r)[1]))
      c.fail("render.range", "render.range = [" + toml_float((*r)[0]) + ", " + toml_float((*r)[1]) +
                                 "] is empty; allowed: [lo, hi] with lo < hi");
    const int msaa = sc.get<int>("render.msaa");
    if (msaa != 0 && (msaa & (msaa - 1)) != 0)
      c.fail("render.msaa", "render.msaa = " + std::to_string(msaa) + " is not allowed; allowed: 0, 1, 2, 4, 8, 16");
    const auto bg = sc.get<std::string>("render.background");
    if (!is_hex_colour(bg))
      c.fail("render.background",
             "render.background = \"" + bg + "\" is not a colour; allowed: \"#rrggbb\" or \"#rrggbbaa\" (hex digits)");
  });

  auto& output = s.section("output", "what the run writes into its folder");
  output.add_bool("png", true, "write frames/NNNNNN.png");
  output.add_bool("mp4", true, "write an H.264 MP4 of the frames");
  output.add_int("fps", 30, "MP4 frame rate", "frames/s").at_least(1).at_most(240);
  output.add_int("crf", 20, "H.264 constant rate factor (lower = better quality, larger file)").at_least(0).at_most(51);
  output.add_enum("preset",
                  {"ultrafast", "superfast", "veryfast", "faster", "fast", "medium", "slow", "slower", "veryslow"},
                  "medium", "H.264 encoder speed/size preset");
  output.add_bool("fields", false, "write the binned fields of every frame (VTK image data, ParaView)");
  output.add_bool("particles", false, "write particle positions and radii of every frame (OVITO-readable)");
  output.add_float("checkpoint_every", 0.0, "simulated time between checkpoints (0 = none)", "time units")
      .at_least(0.0);
  output.add_float("stats_every", 0.0, "simulated time between stats.csv rows (0 = one per frame)", "time units")
      .at_least(0.0);
}

}  // namespace grainflow::scenes
