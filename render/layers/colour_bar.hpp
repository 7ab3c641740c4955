// Colour bars for field panels (SPEC §3 "scalar field maps with colour bars"): the map as
// a vertical strip, ticks at "nice" 1–2–5 values and their labels, and the quantity's
// label above the strip.
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "render/layers/colormap.hpp"
#include "render/layers/field_map_layer.hpp"
#include "render/layers/pixel_rect.hpp"
#include "render/layers/segment_layer.hpp"
#include "render/layers/text_renderer.hpp"

namespace grainflow::render {

// Tick values inside [lo, hi] (inclusive, to 1e-9 of a step) at a step of 1, 2 or 5 × 10^k
// chosen for about `target` ticks (≥ 2). Values within 1e-9 steps of zero are exactly 0.
// Empty when lo ≥ hi or either is not finite.
std::vector<double> nice_ticks(double lo, double hi, int target);
// Step between the ticks nice_ticks() returns (0 when it returns fewer than 2).
double tick_step(const std::vector<double>& ticks);
// A tick label with as many decimals as the step needs ("0.25", "120", "-0.5"); very
// large or small magnitudes in exponent form ("1.5e+06").
std::string format_tick(double value, double step);

struct ColourBarStyle {
  int font_px = 12;
  Rgb ink{0.1f, 0.1f, 0.1f};
  int tick_px = 4;  // tick length
};

// Values the range cut off: a triangle below (above) the strip says that some lie below
// lo (above hi) and are drawn in the end colour.
struct Clipped {
  bool below = false, above = false;
};

// Draws the strip into `bar` now (the current viewport must be the whole width × height
// frame, `pixel` = pixel_view(width, height)) and queues the outline, ticks and clip
// triangles into `overlay` (frame-pixel segments) and the labels into `text`.
void draw_colour_bar(FieldMapLayer& fields, const ViewTransform& pixel, const PixelRect& bar,
                     std::pair<double, double> range, const Colormap& colormap, const std::string& label,
                     const ColourBarStyle& style, std::vector<Segment>& overlay, TextRenderer& text,
                     Clipped clipped = {});

}  // namespace grainflow::render
