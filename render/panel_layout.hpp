// Multi-panel frames (SPEC §3 "multi-panel layouts"; seed 003 Fig. 4.2–4.22 show particles,
// density, temperature and velocity side by side): what each panel shows (PanelSpec), the
// grid they fill row by row (FrameLayout, the scene file's [render] layout/panels), and
// where every panel, title and the caption line sit in the frame (layout_frame).
#pragma once
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "render/layers/colormap.hpp"
#include "render/layers/field_map_layer.hpp"
#include "render/layers/pixel_rect.hpp"
#include "render/layers/streamline_layer.hpp"

namespace grainflow::render {

enum class PanelKind {
  particles,    // the particles (colour attribute, FrameStyle range), obstacles, domain
  field,        // a scalar field of the Snapshot, by name
  streamlines,  // streamlines over the speed map |v| (or |v − U|)
  velocity,     // quiver arrows coloured by speed
};

struct PanelSpec {
  PanelKind kind = PanelKind::particles;
  std::string name;  // its row in the panel table ("density", …); set by panel_from_name
  // PanelKind::field: the Snapshot field's name. "speed" falls back to |velocity| when the
  // snapshot has no field of that name.
  std::string field;
  std::string title;                   // empty: a default from kind and field
  std::optional<Colormap> colormap;    // empty: FrameStyle::colormap
  FieldRange range = FieldRange::percentile(2.0, 98.0);
  FieldFilter filter = FieldFilter::nearest;
  StreamlineStyle streamlines;         // streamlines and velocity panels
  bool colour_bar = true;
};

// The panel names, from the panel table in panel_layout.cpp (the scene schema's [render]
// panels and `render --panels` take them).
std::span<const std::string_view> panel_names();
// A panel with its defaults; throws grainflow::Error naming the value and the allowed names.
PanelSpec panel_from_name(std::string_view name);

// The panels whose map takes a colour range (field and streamline panels): the names a
// scene's [render.ranges] and `render --map-range` accept.
std::vector<std::string_view> ranged_panel_names();

struct FrameLayout {
  int cols = 1, rows = 1;
  std::vector<PanelSpec> panels;  // filled row by row; at most cols × rows
  bool caption = true;            // a caption line when the Snapshot has one
};

// Fixes the colour range of every panel called `name` to [lo, hi]. Throws grainflow::Error
// when the layout has no such panel, it takes no range, or the range is empty/non-finite.
void set_fixed_range(FrameLayout& layout, std::string_view name, double lo, double hi);
// The "run" range mode (render.range_mode): each panel whose range is not fixed keeps the
// range it was first drawn with (`drawn`: FrameRenderer::last_panel_ranges()), so the
// colour scale stays put for the whole video and two runs compare.
void keep_drawn_ranges(FrameLayout& layout, const std::vector<std::optional<std::pair<double, double>>>& drawn);

// Throws grainflow::Error for cols/rows outside 1..8, unknown names, or more panels than
// cols × rows.
FrameLayout make_layout(int cols, int rows, std::span<const std::string> names);

struct PanelGeometry {
  PixelRect panel;  // the whole cell
  PixelRect title;  // strip at its top
  PixelRect plot;   // where the picture goes (viewport); the colour bar sits right of the
                    // drawn domain, inside `panel`
  int title_px = 12, tick_px = 10;
};

struct FrameGeometry {
  std::vector<PanelGeometry> panels;  // one per cell, row by row
  PixelRect caption;                  // h = 0 without a caption
  int caption_px = 12;
};

// Integer pixel rectangles that tile width × height exactly; font sizes scale with the
// panel size (titles 10–28 px).
FrameGeometry layout_frame(const FrameLayout& layout, int width, int height, bool with_caption);

// The panel grid (cols, rows) for `panels` panels in a width × height frame that draws a
// domain of width/height `aspect` largest: every cols from 1 to `panels` with the fewest
// rows that hold them, scored by the area the domain fills in one cell's picture (on a
// wide frame a wide domain gets a column of panels, a square one a row or a 2 × 2 grid).
// Ties go to the grid with fewer empty cells.
std::pair<int, int> fitted_grid(int panels, int width, int height, double aspect, bool with_caption);

}  // namespace grainflow::render
