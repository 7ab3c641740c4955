#include "render/layers/streamline_layer.hpp"

#include <algorithm>
#include <cmath>

namespace grainflow::render {

namespace {
Segment make_segment(const Vec2& a, const Vec2& b, Rgb c, float alpha, float width_px) {
  return {{float(a.x()), float(a.y()), 0.f}, {float(b.x()), float(b.y()), 0.f}, {c.r, c.g, c.b, alpha}, width_px};
}

// A chevron with its tip at `tip`, pointing along the unit vector `dir`, `length` long.
void add_chevron(std::vector<Segment>& out, const Vec2& tip, const Vec2& dir, double length, Rgb c, float alpha,
                 float width_px) {
  const Vec2 n(-dir.y(), dir.x());
  const Vec2 back = tip - length * dir;
  out.push_back(make_segment(back + 0.4 * length * n, tip, c, alpha, width_px));
  out.push_back(make_segment(back - 0.4 * length * n, tip, c, alpha, width_px));
}
}  // namespace

std::pair<double, double> StreamlineLayer::build(const core::VectorField& field, std::span<const SolidCircle> solids,
                                                 const StreamlineStyle& style, const Vec2& reference,
                                                 float pixels_per_unit, std::vector<Segment>& out) {
  const Vec2 ref = style.relative_to_reference ? reference : Vec2(0.0, 0.0);
  const double px = 1.0 / std::max(pixels_per_unit, 1e-6f);  // world length of one pixel
  lines_.clear();
  double max_speed = 0.0;
  std::vector<QuiverArrow> arrows;
  const int stride = style.quiver_stride > 0 ? style.quiver_stride
                                             : std::max(1, std::max(field.grid.nx, field.grid.ny) / 20);
  if (style.quiver) {
    arrows = quiver(field, solids, ref, stride);
    for (const auto& a : arrows) max_speed = std::max(max_speed, a.speed);
  } else {
    StreamlineOptions opt = style.trace;
    opt.reference_velocity = ref;
    lines_ = trace_streamlines(field, solids, opt);
    for (const auto& l : lines_)
      for (const auto& p : l.points) max_speed = std::max(max_speed, p.speed);
  }
  const std::pair<double, double> range =
      style.speed_range ? *style.speed_range : std::pair{0.0, max_speed > 0 ? max_speed : 1.0};
  const double inv_span = range.second > range.first ? 1.0 / (range.second - range.first) : 0.0;
  auto colour = [&](double speed) {
    return style.colour_by_speed ? style.colormap.rgb((speed - range.first) * inv_span) : style.line_colour;
  };

  if (style.quiver) {
    const auto& g = field.grid;
    const double cell = stride * std::min(g.dx(), g.dy());
    const double scale = max_speed > 0 ? 0.9 * cell / max_speed : 0.0;
    for (const auto& a : arrows) {
      if (!(a.speed > 0)) continue;
      const Vec2 half = 0.5 * scale * a.velocity;
      const Rgb c = colour(a.speed);
      out.push_back(make_segment(a.position - half, a.position + half, c, style.alpha, style.width_px));
      const double head = std::min(double(style.arrow_px) * px, 0.45 * 2.0 * half.norm());
      add_chevron(out, a.position + half, a.velocity / a.speed, head, c, style.alpha, style.width_px);
    }
    return range;
  }

  // The tracer steps a fraction of a bin, often under 2 pixels: drawing every step would
  // cost one quad each (µs apiece on llvmpipe). Consecutive points merge into one segment
  // while all of them stay within 0.25 px of its chord and it spans ≤ 24 px (≤ 8 px when
  // colour or width vary along the line).
  const double tol = 0.25 * px, tol2 = tol * tol;
  const double max_len = (style.colour_by_speed || style.taper ? 8.0 : 24.0) * px;
  for (const auto& l : lines_) {
    const auto& pts = l.points;
    const double len = std::max(l.length(), 1e-300);
    auto emit = [&](std::size_t a, std::size_t b) {
      const auto& p = pts[a];
      const auto& q = pts[b];
      float w = style.width_px;
      if (style.taper)
        w *= style.taper_start + (1.0f - style.taper_start) * float(0.5 * (p.arc_length + q.arc_length) / len);
      out.push_back(make_segment(p.position, q.position, colour(0.5 * (p.speed + q.speed)), style.alpha, w));
    };
    std::size_t anchor = 0;
    for (std::size_t j = 2; j < pts.size(); ++j) {
      const Vec2 chord = pts[j].position - pts[anchor].position;
      const double c2 = chord.squaredNorm();
      bool fits = c2 <= max_len * max_len;
      for (std::size_t k = anchor + 1; fits && k < j; ++k) {
        const Vec2 d = pts[k].position - pts[anchor].position;
        const double cross = chord.x() * d.y() - chord.y() * d.x();
        fits = cross * cross <= tol2 * c2;
      }
      if (!fits) {
        emit(anchor, j - 1);
        anchor = j - 1;
      }
    }
    if (pts.size() >= 2) emit(anchor, pts.size() - 1);
  }
  if (style.arrowheads) {
    const auto& g = field.grid;
    const double d_sep = style.trace.separation > 0 ? style.trace.separation
                                                    : style.trace.separation_fraction * (g.hi.x() - g.lo.x());
    const double spacing = style.arrow_spacing > 0 ? style.arrow_spacing : 10.0 * d_sep;
    const double head = double(style.arrow_px) * px;
    // Heads every `spacing` of arc, each line with its own phase (golden-ratio sequence):
    // equal phases line up into distracting columns across parallel lines.
    for (std::size_t k = 0; k < lines_.size(); ++k) {
      const auto& pts = lines_[k].points;
      const double len = lines_[k].length();
      if (pts.size() < 2 || len < 2 * head) continue;
      const double phase = std::fmod(0.5 + 0.6180339887498949 * double(k), 1.0);
      double arc = len < spacing ? 0.5 * len : phase * spacing;
      std::size_t i = 0;
      for (; arc < len; arc += spacing) {
        while (i + 2 < pts.size() && pts[i + 1].arc_length < arc) ++i;
        const auto& p = pts[i];
        const auto& q = pts[i + 1];
        const double seg = q.arc_length - p.arc_length;
        if (!(seg > 0)) continue;
        const double f = std::clamp((arc - p.arc_length) / seg, 0.0, 1.0);
        const Vec2 dir = (q.position - p.position) / (q.position - p.position).norm();
        const Vec2 at = p.position + f * (q.position - p.position);
        add_chevron(out, at + 0.5 * head * dir, dir, head, colour(p.speed + f * (q.speed - p.speed)), style.alpha,
                    style.width_px);
      }
    }
  }
  return range;
}

std::pair<double, double> StreamlineLayer::draw(const ViewTransform& view, int width, int height,
                                                const core::VectorField& field, std::span<const SolidCircle> solids,
                                                const StreamlineStyle& style, const Vec2& reference) {
  batch_.clear();
  const auto range = build(field, solids, style, reference, view.pixels_per_unit, batch_);
  segments_.draw(view, width, height, batch_, false);
  return range;
}

}  // namespace grainflow::render
