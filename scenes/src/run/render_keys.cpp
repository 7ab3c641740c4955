// The [render] keys (render_keys.hpp): what each frame shows and how it is drawn.
#include "scenes/src/run/render_keys.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>

#include "render/layers/colormap.hpp"
#include "render/panel_layout.hpp"
#include "engine/core/error.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/scene/toml_text.hpp"

namespace grainflow::scenes::render_keys {

namespace {

bool is_hex_colour(const std::string& s) {
  if (s.size() != 7 && s.size() != 9) return false;
  if (s[0] != '#') return false;
  for (std::size_t i = 1; i < s.size(); ++i)
    if (!std::isxdigit(static_cast<unsigned char>(s[i]))) return false;
  return true;
}

}  // namespace

std::vector<std::string_view> ranged_panels() { return render::ranged_panel_names(); }

Key<std::array<double, 2>> panel_range(std::string_view panel) {
  // Key paths are views: their text lives here for the life of the program.
  static const std::vector<std::string> paths = [] {
    std::vector<std::string> p;
    for (std::string_view name : ranged_panels()) p.push_back("render.ranges." + std::string(name));
    return p;
  }();
  for (const auto& p : paths)
    if (std::string_view(p).substr(std::string_view("render.ranges.").size()) == panel) return {p};
  throw Error("render.ranges: no map panel named '" + std::string(panel) + "'");
}

void declare(Schema& s, std::vector<std::string> colour_attributes) {
  auto& table = s.section("render", "what each frame shows and how it is drawn");
  table.add_int_array(size, {1280, 720}, {"w", "h"}, "frame size", "pixels")
      .at_least(16)
      .at_most(8192)
      .with_note("odd sizes are padded to even for the H.264 MP4");
  table
      .add_int_array(layout, {1, 1}, {"cols", "rows"},
                     "panel grid of each frame; when absent it is chosen from render.size and the domain's aspect "
                     "so that the domain is drawn largest (a wide stream gets its panels stacked)")
      .at_least(1)
      .at_most(8)
      .optional();
  table
      .add_string_array(panels, {render::panel_names().begin(), render::panel_names().end()}, {"particles"},
                        "panels, filled row by row into the layout")
      .length(1, 64);
  table.add_enum(colormap, {render::Colormap::names().begin(), render::Colormap::names().end()}, "viridis",
                  "colour map of scalar fields and of particles coloured by an attribute");
  table.add_enum(color_by, std::move(colour_attributes), "speed",
                  "particle attribute mapped to colour in the particles panel");
  table.add_float_array(range, {0.0, 1.0}, {"lo", "hi"},
                         "colour range of render.color_by (same unit as the attribute); when absent it is "
                         "taken from the first frame and kept for the whole run")
      .optional();
  table.add_enum(range_mode, {"run", "frame"}, "run",
                 "colour ranges of the maps: \"run\" fixes each from the first frame that draws it and keeps it "
                 "(frames and runs compare; values beyond it are clipped, marked by triangles on the bar), "
                 "\"frame\" takes each frame's own 2nd–98th percentiles");
  table.add_enum(filter, {"bilinear", "nearest"}, "bilinear",
                 "how maps colour between bin centres: interpolated, or each bin one flat colour (shows the bins)");
  table.add_enum(streamlines_frame, {"obstacle", "stream"}, "obstacle",
                 "frame of the streamline and velocity panels: \"obstacle\" draws the mean velocity <v>, "
                 "\"stream\" draws <v> − U, the flow seen moving with the stream (its wake eddies; the "
                 "obstacle's frame where the scene has no stream velocity)");
  auto& fixed = s.optional_table("render.ranges", "fixed colour ranges [lo, hi] of map panels, by panel name");
  for (std::string_view name : ranged_panels())
    fixed.add_float_array(panel_range(name), {0.0, 1.0}, {"lo", "hi"},
                          "fixed colour range of the " + std::string(name) + " panel (its field's unit)")
        .optional();
  table.add_enum(backend, {"auto", "egl", "osmesa"}, "auto",
                  "off-screen GL: EGL (surfaceless/device), OSMesa, or auto = EGL then OSMesa");
  table.add_int(msaa, 4, "multisample anti-aliasing samples per pixel (0 = off)").at_least(0).at_most(16);
  table.add_string(background, "#ffffff", "background colour, \"#rrggbb\" or \"#rrggbbaa\"");
  s.add_check([](const Scene& sc, SceneCheck& c) {
    const auto names = sc.get(panels);
    if (const auto grid = sc.find(layout); grid && names.size() > std::size_t((*grid)[0]) * std::size_t((*grid)[1]))
      c.fail(panels.path, std::to_string(names.size()) + " panels do not fit render.layout = [" +
                                  std::to_string((*grid)[0]) + ", " + std::to_string((*grid)[1]) +
                                  "]; allowed: at most cols × rows = " + std::to_string((*grid)[0] * (*grid)[1]) +
                                  " panels");
    if (auto r = sc.find(range); r && !((*r)[0] < (*r)[1]))
      c.fail(range.path, "render.range = [" + toml_float((*r)[0]) + ", " + toml_float((*r)[1]) +
                                 "] is empty; allowed: [lo, hi] with lo < hi");
    for (std::string_view name : ranged_panels()) {
      const auto r = sc.find(panel_range(name));
      if (!r) continue;
      if (!((*r)[0] < (*r)[1]))
        c.fail(panel_range(name).path, "render.ranges." + std::string(name) + " = [" + toml_float((*r)[0]) + ", " +
                                           toml_float((*r)[1]) + "] is empty; allowed: [lo, hi] with lo < hi");
      if (std::find(names.begin(), names.end(), name) == names.end())
        c.fail(panel_range(name).path, "render.ranges." + std::string(name) + " is given but render.panels has no " +
                                           std::string(name) + " panel; allowed: ranges of the panels drawn");
    }
    if (sc.get(streamlines_frame) == "stream" &&
        std::none_of(names.begin(), names.end(), [](const std::string& n) { return n == "streamlines" || n == "velocity"; }))
      c.fail(streamlines_frame.path, "render.streamlines_frame = \"stream\" but render.panels has no streamlines or "
                                     "velocity panel; allowed: \"obstacle\", or add such a panel");
    const int samples = sc.get(msaa);
    if (samples != 0 && (samples & (samples - 1)) != 0)
      c.fail(msaa.path, "render.msaa = " + std::to_string(samples) + " is not allowed; allowed: 0, 1, 2, 4, 8, 16");
    const auto bg = sc.get(background);
    if (!is_hex_colour(bg))
      c.fail(background.path,
             "render.background = \"" + bg + "\" is not a colour; allowed: \"#rrggbb\" or \"#rrggbbaa\" (hex digits)");
  });
}

}  // namespace grainflow::scenes::render_keys
