// The [render] keys the run loop consumes: frame size, panel layout, colour map, colour
// attribute, colour range, GL backend, anti-aliasing, background. Allowed names come from
// the tables that honour them: render::panel_names(), render::Colormap::names() and the
// engine's colour attributes (engine_table.hpp).
#pragma once
#include <array>
#include <string>
#include <vector>

#include "scenes/src/scene/schema.hpp"

namespace grainflow::scenes::render_keys {

inline constexpr Key<std::array<int, 2>> size{"render.size"};
inline constexpr Key<std::array<int, 2>> layout{"render.layout"};
inline constexpr Key<std::vector<std::string>> panels{"render.panels"};
inline constexpr Key<std::string> colormap{"render.colormap"};
inline constexpr Key<std::string> color_by{"render.color_by"};
inline constexpr Key<std::array<double, 2>> range{"render.range"};
inline constexpr Key<std::string> backend{"render.backend"};
inline constexpr Key<int> msaa{"render.msaa"};
inline constexpr Key<std::string> background{"render.background"};
// How the maps' colour ranges are chosen: "run" (default) fixes each panel's range from the
// first frame that draws it and keeps it for the whole video; "frame": each frame's own
// 2nd–98th percentiles (the bars then change from frame to frame).
inline constexpr Key<std::string> range_mode{"render.range_mode"};
inline constexpr TableKey ranges{"render.ranges"};
// How a map colours between bin centres: "bilinear" (default) or "nearest" (each bin one
// flat colour).
inline constexpr Key<std::string> filter{"render.filter"};
// The frame the streamline and velocity panels see the flow in: "obstacle" (default, the
// mean velocity <v> as it is) or "stream" (<v> − U, moving with the stream's velocity U;
// the obstacle's frame where the scene has no stream).
inline constexpr Key<std::string> streamlines_frame{"render.streamlines_frame"};
// render.ranges.<panel> = [lo, hi]: a fixed range for the panel of that name (the map
// panels of the panel table: density, temperature, speed, streamlines, …).
Key<std::array<double, 2>> panel_range(std::string_view panel);
// The panels render.ranges may name.
std::vector<std::string_view> ranged_panels();

// Declares [render]; `colour_attributes` are the values render.color_by may take.
void declare(Schema& s, std::vector<std::string> colour_attributes);

}  // namespace grainflow::scenes::render_keys
