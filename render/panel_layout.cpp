#include "render/panel_layout.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "engine/core/error.hpp"

namespace grainflow::render {

namespace {

PanelSpec field_panel(std::string field, std::optional<Colormap> colormap = std::nullopt) {
  PanelSpec p;
  p.kind = PanelKind::field;
  p.field = field;
  p.title = std::move(field);
  p.colormap = colormap;
  return p;
}

// The one table of panels: a scene's render.panels and `render --panels` take these
// names. A new panel = one row (and, for a new kind of picture, a PanelKind).
struct PanelRow {
  std::string_view name;
  PanelSpec (*make)();
};
constexpr PanelRow kPanels[] = {
    {"particles", [] { return PanelSpec{}; }},
    {"density", [] { return field_panel("density"); }},
    // Area (2D) or solid (3D, within the slab) fraction: what a packed bed is judged by.
    {"fraction", [] { return field_panel("fraction"); }},
    {"temperature", [] { return field_panel("temperature", Colormap(ColormapId::inferno)); }},
    {"speed", [] { return field_panel("speed"); }},
    // Signed: blue clockwise, red counter-clockwise, grey-white 0 (seed 003's eddies).
    {"vorticity",
     [] {
       PanelSpec p = field_panel("vorticity", Colormap(ColormapId::cool_warm));
       p.range.symmetric = true;
       return p;
     }},
    {"streamlines",
     [] {
       PanelSpec p;
       p.kind = PanelKind::streamlines;
       p.title = "streamlines";
       return p;
     }},
    {"velocity",
     [] {
       PanelSpec p;
       p.kind = PanelKind::velocity;
       p.title = "velocity";
       p.streamlines.quiver = true;
       p.streamlines.colour_by_speed = true;
       p.streamlines.width_px = 1.2f;
       p.streamlines.arrow_px = 5.0f;
       return p;
     }},
};

const std::array<std::string_view, std::size(kPanels)> kNames = [] {
  std::array<std::string_view, std::size(kPanels)> n;
  for (std::size_t i = 0; i < n.size(); ++i) n[i] = kPanels[i].name;
  return n;
}();

}  // namespace

std::span<const std::string_view> panel_names() { return kNames; }

PanelSpec panel_from_name(std::string_view name) {
  for (const auto& row : kPanels)
    if (row.name == name) {
      PanelSpec p = row.make();
      p.name = std::string(name);
      return p;
    }
  std::string allowed;
  for (auto n : kNames) allowed += std::string(allowed.empty() ? "" : ", ") + std::string(n);
  throw Error("panel '" + std::string(name) + "' is not known; allowed: " + allowed);
}

std::vector<std::string_view> ranged_panel_names() {
  std::vector<std::string_view> out;
  for (const auto& row : kPanels) {
    const PanelKind kind = row.make().kind;
    if (kind == PanelKind::field || kind == PanelKind::streamlines) out.push_back(row.name);
  }
  return out;
}

void set_fixed_range(FrameLayout& layout, std::string_view name, double lo, double hi) {
  const auto ranged = ranged_panel_names();
  if (std::find(ranged.begin(), ranged.end(), name) == ranged.end()) {
    std::string allowed;
    for (auto n : ranged) allowed += std::string(allowed.empty() ? "" : ", ") + std::string(n);
    throw Error("a colour range for panel '" + std::string(name) + "': only map panels take one; allowed: " + allowed);
  }
  if (!(std::isfinite(lo) && std::isfinite(hi) && lo < hi))
    throw Error("the colour range of panel '" + std::string(name) + "' must be two finite numbers lo < hi");
  bool found = false;
  for (auto& p : layout.panels)
    if (p.name == name) {
      p.range = FieldRange::fixed(lo, hi);
      found = true;
    }
  if (!found) throw Error("a colour range for panel '" + std::string(name) + "', but no such panel is drawn");
}

void keep_drawn_ranges(FrameLayout& layout, const std::vector<std::optional<std::pair<double, double>>>& drawn) {
  for (std::size_t i = 0; i < drawn.size() && i < layout.panels.size(); ++i)
    if (drawn[i] && layout.panels[i].range.mode != FieldRange::Mode::fixed)
      layout.panels[i].range = FieldRange::fixed(drawn[i]->first, drawn[i]->second);
}

FrameLayout make_layout(int cols, int rows, std::span<const std::string> names) {
  if (cols < 1 || cols > 8 || rows < 1 || rows > 8)
    throw Error("layout " + std::to_string(cols) + " × " + std::to_string(rows) +
                " is not allowed; allowed: 1..8 columns × 1..8 rows");
  if (names.size() > std::size_t(cols) * std::size_t(rows))
    throw Error(std::to_string(names.size()) + " panels do not fit a " + std::to_string(cols) + " × " +
                std::to_string(rows) + " layout; allowed: at most " + std::to_string(cols * rows));
  FrameLayout l;
  l.cols = cols;
  l.rows = rows;
  for (const auto& n : names) l.panels.push_back(panel_from_name(n));
  return l;
}

FrameGeometry layout_frame(const FrameLayout& layout, int width, int height, bool with_caption) {
  FrameGeometry g;
  g.caption_px = std::clamp(int(std::lround(height * 0.022)), 10, 24);
  const int caption_h = with_caption ? int(std::lround(g.caption_px * 1.8)) : 0;
  g.caption = {0, height - caption_h, width, caption_h};
  const int area_h = height - caption_h;
  const int cols = std::max(layout.cols, 1), rows = std::max(layout.rows, 1);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      PanelGeometry p;
      const int x0 = c * width / cols, x1 = (c + 1) * width / cols;
      const int y0 = r * area_h / rows, y1 = (r + 1) * area_h / rows;
      p.panel = {x0, y0, x1 - x0, y1 - y0};
      p.title_px = std::clamp(int(std::lround(std::min(p.panel.h * 0.07, p.panel.w * 0.05))), 10, 28);
      p.tick_px = std::max(9, int(std::lround(p.title_px * 0.8)));
      const int title_h = int(std::lround(p.title_px * 1.7));
      p.title = {x0, y0, p.panel.w, title_h};
      // Room right of the picture for the colour bar, its ticks and labels (≈ 7 digits).
      const int bar_area = int(std::lround(p.tick_px * 6.5));
      p.plot = {x0, y0 + title_h, std::max(p.panel.w - bar_area, 1), std::max(p.panel.h - title_h, 1)};
      g.panels.push_back(p);
    }
  return g;
}

std::pair<int, int> fitted_grid(int panels, int width, int height, double aspect, bool with_caption) {
  panels = std::clamp(panels, 1, 64);
  if (!(aspect > 0) || !std::isfinite(aspect)) aspect = 1.0;
  std::pair<int, int> best{1, 1};
  double best_area = -1;
  int best_empty = 0;
  for (int cols = 1; cols <= std::min(panels, 8); ++cols) {
    const int rows = (panels + cols - 1) / cols;
    if (rows > 8) continue;
    FrameLayout trial;
    trial.cols = cols;
    trial.rows = rows;
    const PixelRect plot = layout_frame(trial, width, height, with_caption).panels.front().plot;
    const double w = std::min<double>(plot.w, plot.h * aspect);  // the domain fitted in
    const double area = w * (w / aspect);
    const int empty = cols * rows - panels;
    // 1 % of area counts as a tie: then the grid with fewer empty cells.
    if (area > best_area * 1.01 || (area > best_area * 0.99 && empty < best_empty)) {
      if (area > best_area) best_area = area;
      best = {cols, rows};
      best_empty = empty;
    }
  }
  return best;
}

}  // namespace grainflow::render
