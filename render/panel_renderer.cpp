#include "render/panel_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "render/layers/colour_bar.hpp"

namespace grainflow::render {

namespace {

// Whether valid values lie below or above the range (drawn as triangles on the bar): a
// fixed or run-wide range clips what a frame's own range would have shown.
template <class Values>
void mark_clipped(const Values& values, const std::vector<std::uint8_t>& mask, std::pair<double, double> range,
                  auto& bar) {
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (!mask.empty() && !mask[k]) continue;
    const double v = values[k];
    if (!std::isfinite(v)) continue;
    if (v < range.first) bar.below = true;
    if (v > range.second) bar.above = true;
  }
}

// The legend entries of categorical colours: each category present, in order, with its
// colour and name; more than kMaxLegend categories (colouring by id) get one line saying so.
constexpr std::size_t kMaxLegend = 16;
std::vector<std::pair<Rgb, std::string>> legend_entries(const Snapshot& s, const Colormap& cmap) {
  std::vector<long long> cats;
  for (float v : s.attribute)
    if (std::isfinite(v)) cats.push_back(std::llround(v));
  std::sort(cats.begin(), cats.end());
  cats.erase(std::unique(cats.begin(), cats.end()), cats.end());
  std::vector<std::pair<Rgb, std::string>> out;
  if (cats.size() > kMaxLegend) {
    out.emplace_back(Colormap::kNanColour, std::to_string(cats.size()) + " " + s.attribute_name + "s");
    return out;
  }
  for (long long k : cats) {
    const std::string name = k >= 1 && std::size_t(k) <= s.category_names.size() ? s.category_names[std::size_t(k - 1)]
                                                                                   : s.attribute_name + " " + std::to_string(k);
    out.emplace_back(cmap.category(k), name);
  }
  return out;
}

}  // namespace


std::string caption_text(const Snapshot& s) {
  if (!s.caption.empty()) return s.caption;
  std::string out;
  for (const auto& [k, v] : s.labels) out += (out.empty() ? "" : "     ") + k + " = " + v;
  return out;
}

PanelRenderer::PanelRenderer(const GlApi& gl) : gl_(gl), text_(gl), fields_(gl), streamlines_(gl) {}

const core::ScalarField& PanelRenderer::speed_field(const core::VectorField& v, const Vec2& reference) {
  speed_.grid = v.grid;
  speed_.values.resize(v.values.size());
  speed_.mask.resize(v.values.size());
  for (std::size_t i = 0; i < v.values.size(); ++i) {
    const Vec2 d = v.values[i] - reference;
    const bool ok = (v.mask.empty() || v.mask[i]) && std::isfinite(d.x()) && std::isfinite(d.y());
    speed_.values[i] = ok ? d.norm() : std::nan("");
    speed_.mask[i] = ok ? 1 : 0;
  }
  return speed_;
}

namespace {
// Frame-pixel bounding box of the world rectangle [lo, hi] seen through `view` in `plot`.
PixelRect projected_rect(const ViewTransform& view, const PixelRect& plot, const Eigen::Vector2d& lo,
                         const Eigen::Vector2d& hi) {
  auto px = [&](double x, double y) {
    const Eigen::Vector2d c = view.ndc(x, y);
    return Eigen::Vector2d(plot.x + (c.x() + 1) * 0.5 * plot.w, plot.y + (1 - c.y()) * 0.5 * plot.h);
  };
  const Eigen::Vector2d a = px(lo.x(), lo.y()), b = px(hi.x(), hi.y());
  const int x0 = int(std::lround(std::min(a.x(), b.x()))), x1 = int(std::lround(std::max(a.x(), b.x())));
  const int y0 = int(std::lround(std::min(a.y(), b.y()))), y1 = int(std::lround(std::max(a.y(), b.y())));
  return {x0, y0, x1 - x0, y1 - y0};
}

// A length of 1, 2 or 5 × 10^k world units, at most `max_len`.
double scale_length(double max_len) {
  if (!(max_len > 0) || !std::isfinite(max_len)) return 0.0;
  const double mag = std::pow(10.0, std::floor(std::log10(max_len)));
  for (double m : {5.0, 2.0, 1.0})
    if (m * mag <= max_len) return m * mag;
  return mag;
}

// Frame-pixel bounding box of the 3D box [lo, hi] seen through `view` in `plot`: where the
// colour bar of a 3D particle panel goes beside it.
PixelRect projected_box(const ViewTransform& view, const PixelRect& plot, const Eigen::Vector3d& lo,
                        const Eigen::Vector3d& hi) {
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  const Mat4 m = view.view_proj();
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector4f c = m * Eigen::Vector4f(float((corner & 1) ? hi.x() : lo.x()), float((corner & 2) ? hi.y() : lo.y()),
                                                  float((corner & 4) ? hi.z() : lo.z()), 1.f);
    if (!(c.w() > 0)) return plot;  // a corner behind the eye: the plot is all there is
    const double px = plot.x + (c.x() / c.w() + 1) * 0.5 * plot.w, py = plot.y + (1 - c.y() / c.w()) * 0.5 * plot.h;
    x0 = std::min(x0, px), x1 = std::max(x1, px), y0 = std::min(y0, py), y1 = std::max(y1, py);
  }
  const int ix0 = std::max(plot.x, int(std::lround(x0))), iy0 = std::max(plot.y, int(std::lround(y0)));
  const int ix1 = std::min(plot.right(), int(std::lround(x1))), iy1 = std::min(plot.bottom(), int(std::lround(y1)));
  if (ix1 <= ix0 || iy1 <= iy0) return plot;
  return {ix0, iy0, ix1 - ix0, iy1 - iy0};
}

std::string default_title(const PanelSpec& p, const Snapshot& s) {
  if (!p.title.empty()) return p.title;
  switch (p.kind) {
    case PanelKind::particles: return s.attribute_name.empty() ? "particles" : "particles: " + s.attribute_name;
    case PanelKind::field: return p.field;
    case PanelKind::streamlines: return "streamlines";
    case PanelKind::velocity: return "velocity";
  }
  return {};
}
}  // namespace

void PanelRenderer::add_scale_bar(const PixelRect& dom, double world_width, const std::string& unit,
                                  const PanelGeometry& g, const Rgb& ink) {
  // Under the domain's lower-left corner, when the panel leaves room for it there: about a
  // fifth of the domain's width, a round number of length units.
  const int below = g.panel.bottom() - dom.bottom();
  if (dom.w < 40 || world_width <= 0 || below < int(1.6 * g.tick_px)) return;
  const double px_per_unit = dom.w / world_width;
  const double len = scale_length(0.2 * world_width);
  if (len <= 0) return;
  const float x0 = float(dom.x), x1 = float(dom.x + len * px_per_unit);
  const float y = float(dom.bottom() + 0.6 * g.tick_px);
  const float cap = float(std::max(2, g.tick_px / 3));
  add_polyline(overlay_, {{x0, y - cap, 0.f}, {x0, y, 0.f}, {x1, y, 0.f}, {x1, y - cap, 0.f}}, ink, 1.5f, 1.0f,
               false);
  char buf[48];
  std::snprintf(buf, sizeof buf, "%g", len);
  const std::string label = std::string(buf) + (unit.empty() ? "" : " " + unit);
  text_.add(label, x1 + 0.5f * g.tick_px, y, std::max(8, int(0.85 * g.tick_px)), ink, TextAlign::left,
            TextAnchor::middle);
}

void PanelRenderer::draw(FrameRenderer& frame, const Snapshot& s, const FrameStyle& style, const FrameLayout& layout,
                         int width, int height) {
  const std::string caption = layout.caption ? caption_text(s) : std::string();
  const FrameGeometry geo = layout_frame(layout, width, height, !caption.empty());
  const bool light = (style.background.r + style.background.g + style.background.b) > 1.5f;
  const Rgb ink = light ? Rgb{0.1f, 0.1f, 0.1f} : Rgb{0.9f, 0.9f, 0.9f};
  const Vec2 reference = s.reference_velocity ? Vec2(*s.reference_velocity) : Vec2(0.0, 0.0);
  solids_.clear();
  for (const auto& c : s.obstacles) solids_.push_back({c.centre, c.radius});
  overlay_.clear();
  bars_.clear();
  legends_.clear();
  ranges_.assign(layout.panels.size(), std::nullopt);
  streamline_count_ = 0;

  // Planar panels show the sampling plane. Its rectangle is the field grid's, which for a
  // 3D snapshot may be the x–z or y–z plane rather than the box's x–y face; for 3D, the
  // outline drawn there is that rectangle alone.
  Eigen::Vector2d plane_lo = s.lo.head<2>(), plane_hi = s.hi.head<2>();
  if (!s.fields.empty()) {
    plane_lo = s.fields.front().field.grid.lo;
    plane_hi = s.fields.front().field.grid.hi;
  } else if (s.velocity) {
    plane_lo = s.velocity->grid.lo;
    plane_hi = s.velocity->grid.hi;
  }
  Snapshot plane_outline;
  const Snapshot* planar_geometry = &s;
  if (s.dim == 3) {
    plane_outline.dim = 2;
    plane_outline.lo = {plane_lo.x(), plane_lo.y(), 0.0};
    plane_outline.hi = {plane_hi.x(), plane_hi.y(), 0.0};
    planar_geometry = &plane_outline;
  }

  gl_.Enable(GL_SCISSOR_TEST);
  const std::size_t n = std::min(layout.panels.size(), geo.panels.size());
  for (std::size_t i = 0; i < n; ++i) {
    const PanelSpec& spec = layout.panels[i];
    const PanelGeometry& g = geo.panels[i];
    const PixelRect& plot = g.plot;
    // GL's window origin is the bottom-left corner.
    gl_.Viewport(plot.x, height - plot.bottom(), plot.w, plot.h);
    gl_.Scissor(plot.x, height - plot.bottom(), plot.w, plot.h);
    const bool planar = spec.kind != PanelKind::particles;
    const ViewTransform view = planar ? fit_2d(plane_lo, plane_hi, plot.w, plot.h)
                                      : frame.scene_view(s, style, plot.w, plot.h);
    const Colormap cmap = spec.colormap ? *spec.colormap : style.colormap;
    std::optional<PendingBar> bar;
    std::optional<PendingLegend> legend;
    std::string missing;
    // A map panel without its field yet: the geometry alone, and what to say instead.
    auto no_field = [&](const std::string& field) {
      frame.draw_geometry(*planar_geometry, style, view, plot.w, plot.h, true);
      return s.fields_pending.empty() ? "no " + field + " field" : s.fields_pending;
    };

    switch (spec.kind) {
      case PanelKind::particles: {
        frame.draw_particles(s, style, view, plot.w, plot.h);
        frame.draw_geometry(s, style, view, plot.w, plot.h);
        if (!s.attribute.empty() && !s.attribute_categorical) {
          const auto range = style.range ? *style.range : finite_range(s.attribute);
          bar = PendingBar{{}, range, style.colormap, s.attribute_name, g.tick_px};
          mark_clipped(s.attribute, {}, range, *bar);
        } else if (!s.attribute.empty()) {
          legend = PendingLegend{0, 0, legend_entries(s, style.colormap), g.tick_px};
        }
        break;
      }
      case PanelKind::field: {
        const core::ScalarField* f = nullptr;
        std::string label = spec.field;
        if (const NamedField* nf = s.field(spec.field)) {
          f = &nf->field;
          if (!nf->label.empty()) label = nf->label;
        } else if (spec.field == "speed" && s.velocity) {
          f = &speed_field(*s.velocity, Vec2(0.0, 0.0));
          label = "|<v>|";  // the speed of the mean velocity, not the mean speed <|v|>
        }
        if (!f) {
          missing = no_field(spec.field);
          break;
        }
        const auto range = resolve_range(*f, spec.range);
        fields_.draw(view, *f, range, cmap, spec.filter, solids_);
        frame.draw_geometry(*planar_geometry, style, view, plot.w, plot.h, true);
        bar = PendingBar{{}, range, cmap, label, g.tick_px};
        mark_clipped(f->values, f->mask, range, *bar);
        ranges_[i] = range;
        break;
      }
      case PanelKind::streamlines:
      case PanelKind::velocity: {
        if (!s.velocity) {
          missing = no_field("velocity");
          break;
        }
        const bool relative = spec.streamlines.relative_to_reference && s.reference_velocity;
        // The speed of the bin's mean velocity (it goes to 0 in a dune), as distinct from
        // the "speed" field <|v|>, the mean speed of the disks (thermal motion included).
        std::string speed_label = relative ? "|<v> − U|" : "|<v>|";
        if (!s.length_unit.empty() && !s.time_unit.empty()) speed_label += " [" + s.length_unit + "/" + s.time_unit + "]";
        std::pair<double, double> range;
        if (spec.kind == PanelKind::streamlines) {
          const auto& speed = speed_field(*s.velocity, relative ? reference : Vec2(0.0, 0.0));
          range = resolve_range(speed, spec.range);
          ranges_[i] = range;
          fields_.draw(view, speed, range, cmap, spec.filter, solids_);
          streamlines_.draw(view, plot.w, plot.h, *s.velocity, solids_, spec.streamlines, reference);
        } else {
          StreamlineStyle st = spec.streamlines;
          st.colormap = cmap;
          range = streamlines_.draw(view, plot.w, plot.h, *s.velocity, solids_, st, reference);
        }
        streamline_count_ += streamlines_.last_line_count();
        frame.draw_geometry(*planar_geometry, style, view, plot.w, plot.h, true);
        bar = PendingBar{{}, range, cmap, speed_label, g.tick_px};
        if (spec.kind == PanelKind::streamlines) mark_clipped(speed_.values, speed_.mask, range, *bar);
        break;
      }
    }

    text_.add(default_title(spec, s), float(g.panel.x + 0.5 * g.panel.w), float(g.title.y + 0.55 * g.title.h),
              g.title_px, ink, TextAlign::centre, TextAnchor::middle);
    if (!missing.empty()) {
      // Centred on the plot, within the panel (a long message would run into the next one):
      // wrapped onto up to three lines, and smaller only if it must be.
      const float cx = float(plot.x + 0.5 * plot.w), cy = float(plot.y + 0.5 * plot.h);
      const float room = 2.0f * std::min(cx - float(g.panel.x), float(g.panel.right()) - cx) - float(g.tick_px);
      const FittedText fitted = fit_text(missing, room, g.tick_px, 3,
                                         [this](std::string_view t, int px) { return text_.measure(t, px); });
      const float step = 1.3f * float(fitted.px);
      for (std::size_t k = 0; k < fitted.lines.size(); ++k)
        text_.add(fitted.lines[k], cx, cy + step * (float(k) - 0.5f * float(fitted.lines.size() - 1)), fitted.px, ink,
                  TextAlign::centre, TextAnchor::middle);
    }
    if (planar || s.dim == 2) {
      const PixelRect dom = planar ? projected_rect(view, plot, plane_lo, plane_hi)
                                   : projected_rect(view, plot, s.lo.head<2>(), s.hi.head<2>());
      const double world_w = planar ? plane_hi.x() - plane_lo.x() : s.hi.x() - s.lo.x();
      add_scale_bar(dom, world_w, s.length_unit, g, ink);
    }
    if (bar && spec.colour_bar) {
      // Beside the drawn domain, as tall as it, leaving room for the label above.
      const PixelRect dom = planar        ? projected_rect(view, plot, plane_lo, plane_hi)
                            : s.dim == 2 ? projected_rect(view, plot, s.lo.head<2>(), s.hi.head<2>())
                                         : projected_box(view, plot, s.lo, s.hi);
      const int gap = std::max(4, int(0.7 * g.tick_px));
      const int top = std::max(dom.y, plot.y + int(2.4 * g.tick_px));  // room for a clip triangle and the label
      const int bottom = std::min(dom.bottom(), g.panel.bottom() - g.tick_px / 2);
      const int x = std::min(dom.right(), plot.right()) + gap;
      bar->rect = {x, top, std::max(6, int(std::lround(0.9 * g.tick_px))), bottom - top};
      bars_.push_back(*bar);
    }
    if (legend && spec.colour_bar) {
      const PixelRect dom = s.dim == 2 ? projected_rect(view, plot, s.lo.head<2>(), s.hi.head<2>())
                                       : projected_box(view, plot, s.lo, s.hi);
      const int gap = std::max(4, int(0.7 * g.tick_px));
      legend->x = std::min(dom.right(), plot.right()) + gap;
      legend->y = std::max(dom.y, plot.y) + g.tick_px;
      legends_.push_back(std::move(*legend));
    }
  }
  gl_.Disable(GL_SCISSOR_TEST);
  gl_.Viewport(0, 0, width, height);

  const ViewTransform pixel = pixel_view(width, height);
  ColourBarStyle bar_style;
  bar_style.ink = ink;
  for (const auto& b : bars_) {
    bar_style.font_px = b.font_px;
    bar_style.tick_px = std::max(3, b.font_px / 3);
    draw_colour_bar(fields_, pixel, b.rect, b.range, b.colormap, b.label, bar_style, overlay_, text_,
                    {b.below, b.above});
  }
  for (const auto& l : legends_) {
    const float side = float(l.font_px), step = 1.6f * float(l.font_px);
    for (std::size_t k = 0; k < l.entries.size(); ++k) {
      const float y = float(l.y) + step * float(k);
      const auto& c = l.entries[k].first;
      // A square swatch: one segment as wide as it is long.
      overlay_.push_back({{float(l.x), y, 0.f}, {float(l.x) + side, y, 0.f}, {c.r, c.g, c.b, 1.f}, side});
      text_.add(l.entries[k].second, float(l.x) + 1.5f * side, y, l.font_px, ink, TextAlign::left, TextAnchor::middle);
    }
  }
  if (!caption.empty()) {
    // One line within the frame's margins: a long caption (a scene's title, then the run's
    // figures) is drawn smaller rather than cut off at the right edge, down to 2/3 of its size.
    const auto measure = [this](std::string_view t, int px) { return text_.measure(t, px); };
    const FittedText fitted = fit_text(caption, float(geo.caption.w - 2 * geo.caption_px), geo.caption_px, 1,
                                       measure, std::max(8, 2 * geo.caption_px / 3));
    text_.add(caption, float(geo.caption_px), float(geo.caption.y + 0.5 * geo.caption.h), fitted.px, ink,
              TextAlign::left, TextAnchor::middle);
  }
  frame.segments_.draw(pixel, width, height, overlay_, false);
  text_.draw(width, height);
}

}  // namespace grainflow::render
