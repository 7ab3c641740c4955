#include "render/plot/plot.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

#include <Eigen/Core>

#include "engine/core/error.hpp"
#include "render/context/framebuffer.hpp"
#include "render/layers/colour_bar.hpp"
#include "render/layers/pixel_rect.hpp"
#include "render/layers/segment_layer.hpp"
#include "render/layers/text_renderer.hpp"

namespace grainflow::render::plot {
namespace {

std::string fmt_g(double v) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

// The value as an axis coordinate: log10 on a log axis.
double axis_coord(double v, bool log) { return log ? std::log10(v) : v; }

std::string point_name(const Figure& f, std::size_t s, std::size_t i) {
  const std::string& label = f.series[s].label;
  return "series " + std::to_string(s + 1) + (label.empty() ? "" : " ('" + label + "')") + ", point " +
         std::to_string(i + 1);
}

}  // namespace

std::vector<Tick> linear_ticks(double lo, double hi, int target) {
  std::vector<Tick> out;
  const std::vector<double> values = nice_ticks(lo, hi, target);
  const double step = tick_step(values);
  for (double v : values) out.push_back({v, format_tick(v, step), true});
  return out;
}

std::string decade_label(int k) {
  static const char* const kSup[] = {"⁰", "¹", "²", "³", "⁴", "⁵", "⁶", "⁷", "⁸", "⁹"};
  std::string s = "10";
  if (k < 0) s += "⁻";
  const std::string digits = std::to_string(std::abs(k));
  for (char d : digits) s += kSup[d - '0'];
  return s;
}

std::vector<Tick> log_ticks(double lo, double hi, int max_labels) {
  std::vector<Tick> out;
  if (!(std::isfinite(lo) && std::isfinite(hi) && lo > 0 && lo < hi)) return out;
  max_labels = std::max(max_labels, 2);
  const double eps = 1e-9;
  const double llo = std::log10(lo), lhi = std::log10(hi);
  const int k_first = int(std::ceil(llo - eps)), k_last = int(std::floor(lhi + eps));
  const int decades = std::max(0, k_last - k_first + 1);
  // Under ~1.7 decades the decade labels alone are too few (1 and 10 on a 1 … 30 axis).
  const bool label_minors = decades < 2 || (lhi - llo) < 1.7;
  // With few decades, which minor mantissas carry labels: 2 and 5 over 0.6 decades, all below.
  const bool all_minors = (lhi - llo) < 0.6;
  const int every = std::max(1, (decades + max_labels - 1) / max_labels);
  auto inside = [&](double v) { return v >= lo * (1 - eps) && v <= hi * (1 + eps); };
  // Decade labels as plain numbers when minor ones are labelled too ("0.001, 0.002, 0.005").
  auto decade_text = [&](int k) { return label_minors && std::abs(k) <= 4 ? fmt_g(std::pow(10.0, k)) : decade_label(k); };
  for (int k = int(std::floor(llo)); k <= k_last; ++k) {
    const double decade = std::pow(10.0, k);
    if (inside(decade)) {
      const bool labelled = label_minors || k % every == 0;
      out.push_back({decade, labelled ? decade_text(k) : "", true});
    }
    for (int j = 2; j <= 9; ++j) {
      const double v = j * decade;
      if (!inside(v)) continue;
      const bool labelled = label_minors && (all_minors || j == 2 || j == 5);
      out.push_back({v, labelled ? fmt_g(v) : "", false});
    }
  }
  const auto labelled = std::count_if(out.begin(), out.end(), [](const Tick& t) { return !t.label.empty(); });
  if (labelled < 2) return linear_ticks(lo, hi, 4);  // under a fifth of a decade: plain numbers
  return out;
}

std::pair<double, double> axis_range(const Figure& f, bool x_axis) {
  const Axis& axis = x_axis ? f.x : f.y;
  const char* name = x_axis ? "x" : "y";
  if (axis.range) {
    const auto [lo, hi] = *axis.range;
    if (!(std::isfinite(lo) && std::isfinite(hi) && lo < hi) || (axis.log && lo <= 0))
      throw Error(std::string("plot: the ") + name + " range [" + fmt_g(lo) + ", " + fmt_g(hi) +
                  "] is not lo < hi" + (axis.log ? " with lo > 0 (log axis)" : ""));
    return *axis.range;
  }
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t s = 0; s < f.series.size(); ++s) {
    const Series& sr = f.series[s];
    for (std::size_t i = 0; i < sr.x.size(); ++i) {
      if (!(std::isfinite(sr.x[i]) && std::isfinite(sr.y[i]))) continue;
      const double v = x_axis ? sr.x[i] : sr.y[i];
      if (axis.log && v <= 0)
        throw Error(std::string("plot: the ") + name + " axis is logarithmic but " + point_name(f, s, i) + " has " +
                    name + " = " + fmt_g(v) + " (≤ 0); allowed: positive values, or a linear axis");
      lo = std::min(lo, v);
      hi = std::max(hi, v);
      if (!x_axis && !sr.y_err.empty() && std::isfinite(sr.y_err[i])) {
        hi = std::max(hi, v + sr.y_err[i]);
        // A bar reaching below zero on a log axis is cut at the axis, not widened to it.
        if (!axis.log || v - sr.y_err[i] > 0) lo = std::min(lo, v - sr.y_err[i]);
      }
    }
  }
  if (!(lo <= hi)) throw Error("plot: no series has a finite point to draw");
  if (axis.log) {
    double llo = std::log10(lo), lhi = std::log10(hi);
    if (lhi - llo < 1e-12) llo -= 0.5, lhi += 0.5;
    const double pad = 0.04 * (lhi - llo);
    return {std::pow(10.0, llo - pad), std::pow(10.0, lhi + pad)};
  }
  if (hi - lo <= 1e-12 * std::max(1.0, std::abs(hi))) {
    const double half = lo == 0 ? 1.0 : 0.1 * std::abs(lo);
    return {lo - half, hi + half};
  }
  const double pad = 0.04 * (hi - lo);
  return {lo - pad, hi + pad};
}

Image draw_figure(GlContext& context, const Figure& f) {
  if (f.width < 120 || f.height < 90 || f.width > 8192 || f.height > 8192)
    throw Error("plot: size " + std::to_string(f.width) + " × " + std::to_string(f.height) +
                " pixels; allowed: 120 × 90 to 8192 × 8192");
  if (f.series.empty()) throw Error("plot: nothing to draw (no series)");
  for (std::size_t s = 0; s < f.series.size(); ++s) {
    const Series& sr = f.series[s];
    if (sr.x.size() != sr.y.size() || (!sr.y_err.empty() && sr.y_err.size() != sr.y.size()))
      throw Error("plot: series " + std::to_string(s + 1) + " has " + std::to_string(sr.x.size()) + " x, " +
                  std::to_string(sr.y.size()) + " y and " + std::to_string(sr.y_err.size()) + " error values");
    for (std::size_t i = 0; i < sr.y_err.size(); ++i)
      if (sr.y_err[i] < 0) throw Error("plot: " + point_name(f, s, i) + " has a negative error bar");
  }
  const auto xr = axis_range(f, true), yr = axis_range(f, false);

  context.make_current();
  const GlApi& gl = context.gl();
  Framebuffer fb(gl, f.width, f.height);
  TextRenderer text(gl);
  SegmentLayer segments(gl);
  const ViewTransform pixel = pixel_view(f.width, f.height);
  const Rgb ink{0.1f, 0.1f, 0.1f}, grid{0.88f, 0.88f, 0.88f};
  const int font = std::clamp(int(std::lround(f.height / 38.0)), 11, 40);
  const int title_font = int(std::lround(font * 1.25));
  const int tick_len = std::max(4, font / 3);

  // Tick sets first: the left margin is as wide as the widest y label.
  const int y_target = std::clamp(f.height / (3 * font), 3, 10), x_target = std::clamp(f.width / (7 * font), 3, 10);
  const std::vector<Tick> xt = f.x.log ? log_ticks(xr.first, xr.second) : linear_ticks(xr.first, xr.second, x_target);
  const std::vector<Tick> yt = f.y.log ? log_ticks(yr.first, yr.second) : linear_ticks(yr.first, yr.second, y_target);
  float widest = 0;
  for (const Tick& t : yt) widest = std::max(widest, text.measure(t.label, font));
  PixelRect area;
  area.x = int(std::ceil(widest)) + tick_len + font;
  const int top = (f.title.empty() ? font : int(2.0 * title_font)) + (f.y.label.empty() ? 0 : int(1.6 * font));
  area.y = top;
  area.w = f.width - area.x - int(1.5 * font);
  area.h = f.height - top - int((f.x.label.empty() ? 1.8 : 3.4) * font);
  if (area.w < 40 || area.h < 30) throw Error("plot: the figure is too small for its labels");

  const double xl = axis_coord(xr.first, f.x.log), xh = axis_coord(xr.second, f.x.log);
  const double yl = axis_coord(yr.first, f.y.log), yh = axis_coord(yr.second, f.y.log);
  auto px = [&](double v) { return float(area.x + (axis_coord(v, f.x.log) - xl) / (xh - xl) * area.w); };
  auto py = [&](double v) {
    // A bar end at y ≤ 0 on a log axis is drawn to below the frame (the scissor cuts it).
    if (f.y.log && v <= 0) return float(area.bottom() + 10);
    return float(area.bottom() - (axis_coord(v, f.y.log) - yl) / (yh - yl) * area.h);
  };
  auto clampf = [](float v) { return std::clamp(v, -1e5f, 1e5f); };
  auto seg = [](std::vector<Segment>& out, float x0, float y0, float x1, float y1, Rgb c, float w, float a = 1.f) {
    out.push_back({{x0, y0, 0.f}, {x1, y1, 0.f}, {c.r, c.g, c.b, a}, w});
  };

  fb.bind();
  gl.ClearColor(1.f, 1.f, 1.f, 1.f);
  gl.ClearDepth(1.0);
  gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

  // Inside the frame: grid lines at the major ticks, then the series (cut at the frame).
  std::vector<Segment> inner;
  for (const Tick& t : xt)
    if (t.major) seg(inner, px(t.value), float(area.y), px(t.value), float(area.bottom()), grid, 1.f);
  for (const Tick& t : yt)
    if (t.major) seg(inner, float(area.x), py(t.value), float(area.right()), py(t.value), grid, 1.f);
  const Colormap tab10(ColormapId::tab10);
  auto colour_of = [&](std::size_t s) { return f.series[s].colour.value_or(tab10.category(long(s))); };
  for (std::size_t s = 0; s < f.series.size(); ++s) {
    const Series& sr = f.series[s];
    const Rgb c = colour_of(s);
    if (sr.style != SeriesStyle::points) {
      // Runs of finite points; dashes are measured along the line in pixels.
      std::vector<Eigen::Vector2f> run;
      auto flush = [&] {
        if (run.size() >= 2 && !sr.dashed) {
          for (std::size_t i = 0; i + 1 < run.size(); ++i)
            seg(inner, run[i].x(), run[i].y(), run[i + 1].x(), run[i + 1].y(), c, sr.width_px);
        } else if (run.size() >= 2) {
          const float on = 4.f * sr.width_px + 2.f, off = 2.5f * sr.width_px + 2.f;
          float phase = 0;  // distance into the current on+off period
          for (std::size_t i = 0; i + 1 < run.size(); ++i) {
            const Eigen::Vector2f a = run[i], d = run[i + 1] - run[i];
            const float len = d.norm();
            float done = 0;
            while (done < len) {
              const bool drawing = phase < on;
              const float step = std::min(len - done, drawing ? on - phase : on + off - phase);
              if (drawing) {
                const Eigen::Vector2f p0 = a + d * (done / len), p1 = a + d * ((done + step) / len);
                seg(inner, p0.x(), p0.y(), p1.x(), p1.y(), c, sr.width_px);
              }
              done += step;
              phase = std::fmod(phase + step, on + off);
            }
          }
        }
        run.clear();
      };
      for (std::size_t i = 0; i < sr.x.size(); ++i) {
        if (std::isfinite(sr.x[i]) && std::isfinite(sr.y[i])) run.emplace_back(clampf(px(sr.x[i])), clampf(py(sr.y[i])));
        else flush();
      }
      flush();
    }
    const float mark = std::max(4.f, 2.5f * sr.width_px);
    for (std::size_t i = 0; i < sr.x.size(); ++i) {
      if (!(std::isfinite(sr.x[i]) && std::isfinite(sr.y[i]))) continue;
      const float x = clampf(px(sr.x[i])), y = clampf(py(sr.y[i]));
      if (!sr.y_err.empty() && std::isfinite(sr.y_err[i]) && sr.y_err[i] > 0) {
        const float y0 = clampf(py(sr.y[i] - sr.y_err[i])), y1 = clampf(py(sr.y[i] + sr.y_err[i]));
        seg(inner, x, y0, x, y1, c, 1.25f);
        for (float yc : {y0, y1}) seg(inner, x - mark * 0.6f, yc, x + mark * 0.6f, yc, c, 1.25f);
      }
      // A filled square: a segment of (almost) no length is drawn as a square of its width.
      if (sr.style != SeriesStyle::line) seg(inner, x - 0.01f, y, x + 0.01f, y, c, mark);
    }
  }
  gl.Enable(GL_SCISSOR_TEST);
  gl.Scissor(area.x, f.height - area.bottom(), area.w, area.h);
  segments.draw(pixel, f.width, f.height, inner);
  gl.Disable(GL_SCISSOR_TEST);

  // The frame, ticks (outward; minor ones half as long) and their labels.
  std::vector<Segment> outer;
  add_polyline(outer,
               {{float(area.x), float(area.y), 0.f},
                {float(area.right()), float(area.y), 0.f},
                {float(area.right()), float(area.bottom()), 0.f},
                {float(area.x), float(area.bottom()), 0.f}},
               ink, 1.f, 1.f, true);
  for (const Tick& t : xt) {
    const float x = px(t.value), len = float(t.major ? tick_len : tick_len / 2);
    seg(outer, x, float(area.bottom()), x, float(area.bottom()) + len, ink, 1.f);
    if (!t.label.empty())
      text.add(t.label, x, float(area.bottom() + tick_len + 3), font, ink, TextAlign::centre, TextAnchor::top);
  }
  for (const Tick& t : yt) {
    const float y = py(t.value), len = float(t.major ? tick_len : tick_len / 2);
    seg(outer, float(area.x) - len, y, float(area.x), y, ink, 1.f);
    if (!t.label.empty())
      text.add(t.label, float(area.x - tick_len - 3), y, font, ink, TextAlign::right, TextAnchor::middle);
  }
  segments.draw(pixel, f.width, f.height, outer);
  if (!f.title.empty())
    text.add(f.title, 0.5f * f.width, 0.4f * title_font, title_font, ink, TextAlign::centre, TextAnchor::top);
  if (!f.y.label.empty())
    text.add(f.y.label, float(area.x), float(area.y) - 0.6f * font, font, ink, TextAlign::left, TextAnchor::baseline);
  if (!f.x.label.empty())
    text.add(f.x.label, float(area.x + 0.5 * area.w), float(f.height) - 0.6f * font, font, ink, TextAlign::centre,
             TextAnchor::baseline);

  // The legend, top right inside the frame, on white: a line (or marker) sample per
  // labelled series.
  std::vector<std::size_t> listed;
  float label_w = 0;
  for (std::size_t s = 0; s < f.series.size(); ++s)
    if (!f.series[s].label.empty()) {
      listed.push_back(s);
      label_w = std::max(label_w, text.measure(f.series[s].label, font));
    }
  if (!listed.empty()) {
    const int line_h = int(1.5 * font), sample = 2 * font, pad = font / 2;
    PixelRect box;
    box.w = std::min(area.w - 2 * pad, int(std::ceil(label_w)) + sample + 3 * pad);
    box.h = std::min(area.h - 2 * pad, int(listed.size()) * line_h + 2 * pad);
    // The corner (top right, top left, bottom right, bottom left) whose box covers the
    // fewest points of the series: the legend hides as little data as it can.
    const std::array<std::pair<int, int>, 4> corners = {{{area.right() - box.w - pad, area.y + pad},
                                                         {area.x + pad, area.y + pad},
                                                         {area.right() - box.w - pad, area.bottom() - box.h - pad},
                                                         {area.x + pad, area.bottom() - box.h - pad}}};
    std::size_t best = 0, best_count = std::numeric_limits<std::size_t>::max();
    for (std::size_t k = 0; k < corners.size(); ++k) {
      std::size_t count = 0;
      const auto [cx, cy] = corners[k];
      for (const Series& sr : f.series)
        for (std::size_t i = 0; i < sr.x.size(); ++i) {
          if (!(std::isfinite(sr.x[i]) && std::isfinite(sr.y[i]))) continue;
          const float x = px(sr.x[i]), y = py(sr.y[i]);
          count += x >= cx - pad && x <= cx + box.w + pad && y >= cy - pad && y <= cy + box.h + pad;
        }
      if (count < best_count) best = k, best_count = count;
    }
    box.x = corners[best].first;
    box.y = corners[best].second;
    gl.Enable(GL_SCISSOR_TEST);
    gl.Scissor(box.x, f.height - box.bottom(), box.w, box.h);
    gl.Clear(GL_COLOR_BUFFER_BIT);
    gl.Disable(GL_SCISSOR_TEST);
    std::vector<Segment> legend;
    add_polyline(legend,
                 {{float(box.x), float(box.y), 0.f},
                  {float(box.right()), float(box.y), 0.f},
                  {float(box.right()), float(box.bottom()), 0.f},
                  {float(box.x), float(box.bottom()), 0.f}},
                 Rgb{0.6f, 0.6f, 0.6f}, 1.f, 1.f, true);
    for (std::size_t k = 0; k < listed.size(); ++k) {
      const Series& sr = f.series[listed[k]];
      const Rgb c = colour_of(listed[k]);
      const float y = float(box.y + pad) + (float(k) + 0.5f) * float(line_h);
      const float x0 = float(box.x + pad), x1 = x0 + float(sample);
      if (sr.style != SeriesStyle::points) {
        if (sr.dashed) {
          const float third = (x1 - x0) / 3.f;
          seg(legend, x0, y, x0 + third * 0.8f, y, c, sr.width_px);
          seg(legend, x1 - third * 0.8f, y, x1, y, c, sr.width_px);
        } else {
          seg(legend, x0, y, x1, y, c, sr.width_px);
        }
      }
      if (sr.style != SeriesStyle::line) {
        const float mid = 0.5f * (x0 + x1);
        seg(legend, mid - 0.01f, y, mid + 0.01f, y, c, std::max(4.f, 2.5f * sr.width_px));
      }
      text.add(sr.label, x1 + float(pad), y, font, ink, TextAlign::left, TextAnchor::middle);
    }
    segments.draw(pixel, f.width, f.height, legend);
  }
  text.draw(f.width, f.height);
  Image image;
  fb.read(image);
  return image;
}

}  // namespace grainflow::render::plot
