// Line plots drawn by grainflow itself (issue 13, item 6): `grainflow plot` and the plots
// the study scenes write. A Figure is data (series of x, y and optional error bars, two
// axes, a title); draw_figure() turns it into an Image with the renderer's own machinery
// (thick anti-aliased segments, FreeType/DejaVu text, the tab10 colours), so a plot looks
// like the frames and is the same pixels on every run. Knows no physics and no files.
#pragma once
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "render/context/gl_context.hpp"
#include "render/image/image.hpp"
#include "render/layers/colormap.hpp"

namespace grainflow::render::plot {

enum class SeriesStyle { line, points, line_points };

struct Series {
  std::string label;            // in the legend; a series with an empty label is not listed
  std::vector<double> x, y;     // same length; a non-finite pair is skipped (a line breaks there)
  std::vector<double> y_err;    // empty, or one half-width per point (drawn as a bar with caps)
  SeriesStyle style = SeriesStyle::line;
  bool dashed = false;          // predictions and reference curves
  std::optional<Rgb> colour;    // default: tab10 colour of the series' index
  float width_px = 2.0f;
};

struct Axis {
  std::string label;
  bool log = false;
  // Fixed [lo, hi]; default: the data's range (with error bars) padded by 4 % of its span
  // (of its span in decades on a log axis).
  std::optional<std::pair<double, double>> range;
};

struct Figure {
  std::string title;
  Axis x, y;
  std::vector<Series> series;
  int width = 800, height = 560;
};

// One tick of an axis: its value, its label ("" = a minor tick without a label).
struct Tick {
  double value = 0;
  std::string label;
  bool major = true;
};

// Linear axis ticks: render::nice_ticks (1-2-5 steps) for about `target` labelled ticks
// inside [lo, hi], labels by render::format_tick. Empty when lo ≥ hi or either is not finite.
std::vector<Tick> linear_ticks(double lo, double hi, int target);
// Log axis ticks over [lo, hi] (0 < lo < hi): a major tick at every decade 10^k inside it,
// labelled "10ᵏ" (every m-th decade when more than `max_labels` would be labelled), minor
// ticks at 2..9 × 10^k. When fewer than two decades fall inside (or the span is under 1.7
// decades), the 2 and 5 (spans over 0.6 decades) or every 1..9 (narrower) minor ticks are
// labelled too, all as plain numbers ("0.002", "0.005", "0.01"); under a fifth of a
// decade the labels are linear_ticks'. An axis never has fewer than two labels. Empty for a range
// that is not positive and finite.
std::vector<Tick> log_ticks(double lo, double hi, int max_labels = 8);
// "10⁻³", "10⁰", "10¹²": superscript digits of DejaVu Sans.
std::string decade_label(int k);

// The range an axis shows for the figure's data (see Axis::range). Throws grainflow::Error
// when a log axis meets a value ≤ 0 (naming the series, the point and the value), when no
// series has a finite point, or when a fixed range is not lo < hi (log: 0 < lo).
std::pair<double, double> axis_range(const Figure& f, bool x_axis);

// Checks the figure (series lengths, error bars ≥ 0, the axis ranges) and draws it into an
// Image of f.width × f.height on `context` (made current here). Throws grainflow::Error
// naming what is wrong; the font as FrameRenderer's (find_default_font()).
Image draw_figure(GlContext& context, const Figure& f);

}  // namespace grainflow::render::plot
