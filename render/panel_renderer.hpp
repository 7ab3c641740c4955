// Draws a FrameLayout (render/panel_layout.hpp) into the FrameRenderer's framebuffer: per
// panel a viewport and scissor, its picture (particles, field map, streamlines, quiver),
// obstacles and walls on top; then, over the whole frame, colour bars, titles and the
// caption — all text in one instanced batch, all overlay lines in one segment batch.
#pragma once
#include <optional>
#include <utility>
#include <vector>
#include <string>
#include <utility>
#include <vector>

#include "engine/core/field_grid.hpp"
#include "render/frame_renderer.hpp"
#include "render/layers/field_map_layer.hpp"
#include "render/layers/streamline_layer.hpp"
#include "render/layers/text_renderer.hpp"

namespace grainflow::render {

// The caption line of a snapshot: its caption, else "k = v" labels joined by spaces.
std::string caption_text(const Snapshot& s);

class PanelRenderer {
public:
  explicit PanelRenderer(const GlApi& gl);

  // Into the currently bound width × height framebuffer (already cleared).
  void draw(FrameRenderer& frame, const Snapshot& s, const FrameStyle& style, const FrameLayout& layout, int width,
            int height);

  TextRenderer& text() { return text_; }
  std::size_t last_streamline_count() const { return streamline_count_; }
  // Per panel of the last draw: the colour range of its map (field and streamline panels
  // that had their field), so a caller can keep it for the frames that follow.
  const std::vector<std::optional<std::pair<double, double>>>& last_ranges() const { return ranges_; }

private:
  struct PendingBar {
    PixelRect rect;
    std::pair<double, double> range;
    Colormap colormap;
    std::string label;
    int font_px;
    bool below = false, above = false;  // values were clipped at lo / hi
  };

  // A legend of categorical colours (particles coloured by type): one swatch per category.
  struct PendingLegend {
    int x = 0, y = 0;
    std::vector<std::pair<Rgb, std::string>> entries;
    int font_px;
  };

  // |v − reference| on the velocity grid; invalid where v is masked or not finite.
  const core::ScalarField& speed_field(const core::VectorField& v, const Vec2& reference);
  // A scale bar of a round length under the drawn domain `dom` (frame pixels), whose world
  // width is `world_width` in `unit`: the frames' axes in σ (ED) or m (DEM).
  void add_scale_bar(const PixelRect& dom, double world_width, const std::string& unit, const PanelGeometry& g,
                     const Rgb& ink);

  const GlApi& gl_;
  TextRenderer text_;
  FieldMapLayer fields_;
  StreamlineLayer streamlines_;
  core::ScalarField speed_;
  std::vector<SolidCircle> solids_;
  std::vector<Segment> overlay_;
  std::vector<PendingBar> bars_;
  std::vector<PendingLegend> legends_;
  std::vector<std::optional<std::pair<double, double>>> ranges_;
  std::size_t streamline_count_ = 0;
};

}  // namespace grainflow::render
