#include "render/layers/colour_bar.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace grainflow::render {

std::vector<double> nice_ticks(double lo, double hi, int target) {
  std::vector<double> out;
  if (!(std::isfinite(lo) && std::isfinite(hi) && lo < hi)) return out;
  target = std::max(target, 2);
  const double raw = (hi - lo) / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double norm = raw / mag;
  const double step = (norm < 1.5 ? 1.0 : norm < 3.0 ? 2.0 : norm < 7.0 ? 5.0 : 10.0) * mag;
  const double first = std::ceil(lo / step - 1e-9);
  const double last = std::floor(hi / step + 1e-9);
  for (double k = first; k <= last; k += 1.0) {
    double v = k * step;  // k·step, not repeated addition: no drift
    if (std::abs(v) < 1e-9 * step) v = 0.0;
    out.push_back(v);
  }
  return out;
}

double tick_step(const std::vector<double>& ticks) { return ticks.size() < 2 ? 0.0 : ticks[1] - ticks[0]; }

std::string format_tick(double value, double step) {
  char buf[64];
  const double mag = std::max(std::abs(value), std::abs(step));
  if (mag >= 1e5 || (step > 0 && step < 1e-4)) {
    std::snprintf(buf, sizeof buf, "%.2g", value);
  } else {
    const int decimals = step > 0 ? std::clamp(int(-std::floor(std::log10(step) + 1e-9)), 0, 6) : 2;
    std::snprintf(buf, sizeof buf, "%.*f", decimals, value);
  }
  std::string s = buf;
  if (s.find_first_not_of("-0.") == std::string::npos && !s.empty() && s[0] == '-') s.erase(0, 1);  // no "-0"
  return s;
}

void draw_colour_bar(FieldMapLayer& fields, const ViewTransform& pixel, const PixelRect& bar,
                     std::pair<double, double> range, const Colormap& colormap, const std::string& label,
                     const ColourBarStyle& style, std::vector<Segment>& overlay, TextRenderer& text,
                     Clipped clipped) {
  if (bar.w < 2 || bar.h < 4) return;
  const double x0 = bar.x, x1 = bar.right(), y_top = bar.y, y_bottom = bar.bottom();
  fields.draw_gradient(pixel, {x0, y_bottom}, {x1, y_top}, colormap);
  const std::vector<Eigen::Vector3f> box = {{float(x0), float(y_top), 0.f},
                                            {float(x1), float(y_top), 0.f},
                                            {float(x1), float(y_bottom), 0.f},
                                            {float(x0), float(y_bottom), 0.f}};
  add_polyline(overlay, box, style.ink, 1.0f, 1.0f, true);
  // Clip triangles, as wide as the strip, pointing away from it; filled with the end
  // colour (lines from the apex to the base), outlined in ink.
  const double tri = std::max(4.0, 0.8 * (x1 - x0));
  auto triangle = [&](double base_y, double apex_y, double t) {
    const Rgb fill = colormap.rgb(t);
    const double xm = 0.5 * (x0 + x1);
    for (double x = x0 + 0.5; x < x1; x += 1.0)
      overlay.push_back({{float(x), float(base_y), 0.f}, {float(xm), float(apex_y), 0.f},
                         {fill.r, fill.g, fill.b, 1.0f}, 1.0f});
    add_polyline(overlay, {{float(x0), float(base_y), 0.f}, {float(xm), float(apex_y), 0.f},
                           {float(x1), float(base_y), 0.f}},
                 style.ink, 1.0f, 1.0f, false);
  };
  if (clipped.above) triangle(y_top - 1.0, y_top - 1.0 - tri, 1.0);
  if (clipped.below) triangle(y_bottom + 1.0, y_bottom + 1.0 + tri, 0.0);

  const auto [lo, hi] = range;
  const int target = std::clamp(int(bar.h / (2.2 * style.font_px)), 2, 8);
  const std::vector<double> ticks = nice_ticks(lo, hi, target);
  const double step = tick_step(ticks);
  for (double v : ticks) {
    const float y = float(y_bottom - (v - lo) / (hi - lo) * (y_bottom - y_top));
    overlay.push_back({{float(x1), y, 0.f}, {float(x1 + style.tick_px), y, 0.f},
                       {style.ink.r, style.ink.g, style.ink.b, 1.0f}, 1.0f});
    text.add(format_tick(v, step), float(x1 + style.tick_px + 3), y, style.font_px, style.ink, TextAlign::left,
             TextAnchor::middle);
  }
  // Above the strip, and above the clip triangle when there is one.
  if (!label.empty())
    text.add(label, float(x0), float(y_top - 0.45 * style.font_px - (clipped.above ? tri + 1.0 : 0.0)),
             style.font_px, style.ink, TextAlign::left, TextAnchor::baseline);
}

}  // namespace grainflow::render
