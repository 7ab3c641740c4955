// Field rendering on both off-screen backends: a 2×2 panel frame of analytic fields
// (particles | Gaussian density blob | linear temperature ramp | streamlines of potential
// flow past a cylinder over |v|) with titles, colour bars and a caption, against a golden
// image; masked/NaN/inf bins in exactly the neutral colour; constant fields; ticks.
//
// Comparator thresholds (render/image/compare.hpp): a pixel counts as different when its
// largest channel differs by more than kMaxChannel = 16 levels; at most kMaxFraction =
// 0.2 % of the pixels (512 of 640×400) may differ. Looser than gl_render_test.cpp because
// this frame also holds FreeType text (glyph rasterisation moves by a level or two with
// the FreeType version) and ~4,000 anti-aliased streamline segments whose edge pixels
// round differently across Mesa/LLVM versions. Goldens: Mesa 22.3 llvmpipe, FreeType
// 2.12, DejaVu Sans 2.37. A changed field value changes thousands of pixels by far more
// (ChangedFieldFailsComparison proves the comparator notices it).
//
// GRAINFLOW_UPDATE_GOLDEN=1 rewrites the golden images (commit them with the reason).
// On failure the actual image and a diff heat map are written to GRAINFLOW_TEST_OUT.
#include <gtest/gtest.h>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "engine/core/binning.hpp"
#include "engine/core/error.hpp"
#include "engine/core/rng.hpp"
#include "render/context/embedded_shaders.hpp"
#include "render/context/gl_context.hpp"
#include "render/context/shader_program.hpp"
#include "render/frame_renderer.hpp"
#include "render/image/compare.hpp"
#include "render/layers/colour_bar.hpp"
#include "render/layers/segment_layer.hpp"
#include "render/layers/text_renderer.hpp"
#include "render/output/png_io.hpp"
#include "tests/render/golden_support.hpp"
#include "render/panel_renderer.hpp"

namespace fs = std::filesystem;
using namespace grainflow;
using namespace grainflow::render;
using grainflow::Vec2;

namespace {

constexpr int kMaxChannel = 16;
constexpr double kMaxFraction = 0.002;

constexpr double kCx = 3.0, kCy = 2.5, kA = 0.6;  // cylinder in the 8 × 5 domain

core::GridGeometry grid(int nx = 48, int ny = 30) {
  core::GridGeometry g;
  g.nx = nx;
  g.ny = ny;
  g.lo = Vec2(0, 0);
  g.hi = Vec2(8, 5);
  return g;
}

Vec2 cylinder_velocity(const Vec2& q) {
  const Vec2 p = q - Vec2(kCx, kCy);
  const double r2 = p.squaredNorm(), r4 = r2 * r2;
  return {1.0 - kA * kA * (p.x() * p.x() - p.y() * p.y()) / r4, -2.0 * kA * kA * p.x() * p.y() / r4};
}

// The analytic scene: potential flow past a cylinder, bins inside it masked (NaN data).
Snapshot field_scene() {
  Snapshot s;
  s.dim = 2;
  s.lo = {0, 0, 0};
  s.hi = {8, 5, 0};
  s.obstacles.push_back({{kCx, kCy}, kA});
  const auto g = grid();
  core::ScalarField density(g), temperature(g);
  core::VectorField velocity(g);
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) {
      const Vec2 c = g.centre(ix, iy);
      const bool solid = (c - Vec2(kCx, kCy)).norm() < kA;
      const auto k = g.index(ix, iy);
      density.values[k] = 0.2 + 0.6 * std::exp(-(c - Vec2(5.5, 2.0)).squaredNorm() / 0.8);
      temperature.values[k] = 0.01 + 0.004 * c.x();
      velocity.values[k] = cylinder_velocity(c);
      if (solid) {
        density.mask[k] = temperature.mask[k] = velocity.mask[k] = 0;
        density.values[k] = temperature.values[k] = std::nan("");
        velocity.values[k] = Vec2(std::nan(""), std::nan(""));
      }
    }
  s.fields.push_back({"density", "n", density});
  s.fields.push_back({"temperature", "kT", temperature});
  s.velocity = velocity;
  s.reference_velocity = Eigen::Vector2d(1.0, 0.0);
  // Disks on a jittered lattice, coloured by the analytic speed; ≥ 5,000 so that the
  // software path splats them on the CPU (exercises the panel viewport offset).
  core::Rng rng(3);
  for (int j = 0; j < 62; ++j)
    for (int i = 0; i < 100; ++i) {
      const double x = 0.04 + i * 0.08 + 0.01 * rng.uniform(-1, 1), y = 0.04 + j * 0.08 + 0.01 * rng.uniform(-1, 1);
      if (std::hypot(x - kCx, y - kCy) < kA + 0.04) continue;
      s.pos_radius.insert(s.pos_radius.end(), {float(x), float(y), 0.f, 0.035f});
      s.attribute.push_back(float(cylinder_velocity({x, y}).norm()));
    }
  s.attribute_name = "speed";
  s.labels = {{"t", "12.5"}, {"U", "1"}, {"Re", "40"}, {"τ_E", "480"}, {"N", std::to_string(s.size())}};
  return s;
}

FrameLayout layout_2x2() {
  const std::vector<std::string> names = {"particles", "density", "temperature", "streamlines"};
  FrameLayout l = make_layout(2, 2, names);
  l.panels[3].streamlines.trace.separation = 0.22;
  return l;
}

class FieldRender : public ::testing::TestWithParam<Backend> {
protected:
  void SetUp() override {
    ctx_ = golden::context_or_null(GetParam());
    if (!ctx_) GTEST_SKIP() << "no " << backend_name(GetParam()) << " context on this machine";
  }
  std::unique_ptr<GlContext> ctx_;
};

TEST_P(FieldRender, PanelFrameMatchesGolden) {
  FrameRenderer r(*ctx_, 640, 400);
  FrameStyle style;
  style.range = std::pair{0.0, 1.6};
  golden::check_golden(r.render(field_scene(), style, layout_2x2()), "fields_2x2", {kMaxChannel, kMaxFraction});
}

TEST_P(FieldRender, QuiverAndSpeedPanelsMatchGolden) {
  FrameRenderer r(*ctx_, 480, 200);
  const std::vector<std::string> names = {"speed", "velocity"};
  FrameLayout l = make_layout(2, 1, names);
  l.panels[0].filter = FieldFilter::bilinear;
  l.panels[0].colormap = Colormap(ColormapId::magma);
  Snapshot s = field_scene();
  s.pos_radius.clear();
  s.attribute.clear();
  s.caption = "quiver and bilinear |v|";
  golden::check_golden(r.render(s, FrameStyle{}, l), "fields_quiver", {kMaxChannel, kMaxFraction});
}

// The flow past the cylinder has vorticity of both signs (above and below it): the panel's
// range is symmetric about 0, which the diverging map draws in its light centre.
TEST_P(FieldRender, VorticityPanelIsSignedAndMatchesGolden) {
  FrameRenderer r(*ctx_, 320, 220);
  const std::vector<std::string> names = {"vorticity"};
  FrameLayout l = make_layout(1, 1, names);
  l.panels[0].filter = FieldFilter::bilinear;
  Snapshot s = field_scene();
  s.pos_radius.clear();
  s.attribute.clear();
  s.fields.push_back({"vorticity", "ω", core::vorticity(*s.velocity)});
  s.caption = "vorticity, symmetric range";
  const Image& img = r.render(s, FrameStyle{}, l);
  ASSERT_EQ(r.last_panel_ranges().size(), 1u);
  ASSERT_TRUE(r.last_panel_ranges()[0].has_value());
  const auto [lo, hi] = *r.last_panel_ranges()[0];
  EXPECT_GT(hi, 0.0);
  EXPECT_DOUBLE_EQ(lo, -hi);
  golden::check_golden(img, "fields_vorticity", {kMaxChannel, kMaxFraction});
}

TEST_P(FieldRender, ChangedFieldFailsComparison) {
  FrameRenderer r(*ctx_, 640, 400);
  Snapshot s = field_scene();
  const FrameLayout l = layout_2x2();
  const Image before = r.render(s, {}, l);
  // A 6 × 6-bin cold spot in the temperature ramp (still inside its percentile range).
  auto& t = s.fields[1].field;
  for (int iy = 18; iy < 24; ++iy)
    for (int ix = 34; ix < 40; ++ix) t.at(ix, iy) = 0.012;
  const Image after = r.render(s, {}, l);
  const auto res = compare_images(before, after, {kMaxChannel, kMaxFraction});
  EXPECT_FALSE(res.passed);
  EXPECT_GT(res.max_channel_diff, 60);
  // And the same frame twice is pixel-identical (deterministic, text included).
  const Image again = r.render(s, {}, l);
  EXPECT_EQ(after.rgba, again.rgba);
}

// One field filling a 1×1 layout without caption or bar: the plot is a known rectangle.
struct SinglePanel {
  FrameLayout layout;
  Snapshot s;
  SinglePanel(const core::ScalarField& f, FieldFilter filter) {
    PanelSpec p = panel_from_name("density");
    p.filter = filter;
    p.colour_bar = false;
    p.range = FieldRange::fixed(0.0, 1.0);
    layout.panels = {p};
    layout.caption = false;
    s.dim = 2;
    s.lo = {f.grid.lo.x(), f.grid.lo.y(), 0};
    s.hi = {f.grid.hi.x(), f.grid.hi.y(), 0};
    s.fields.push_back({"density", "", f});
  }
  // Frame pixel at world point p.
  std::pair<int, int> pixel(const Vec2& p, int width, int height) const {
    const auto g = layout_frame(layout, width, height, false).panels[0];
    const ViewTransform v = fit_2d(s.lo.head<2>(), s.hi.head<2>(), g.plot.w, g.plot.h);
    const Eigen::Vector4f c = v.view_proj() * Eigen::Vector4f(float(p.x()), float(p.y()), 0.f, 1.f);
    return {int(g.plot.x + (c.x() + 1) * 0.5 * g.plot.w), int(g.plot.y + (1 - c.y()) * 0.5 * g.plot.h)};
  }
  // World point at the centre of frame pixel (px, py).
  Vec2 world(int px, int py, int width, int height) const {
    const auto g = layout_frame(layout, width, height, false).panels[0];
    const ViewTransform v = fit_2d(s.lo.head<2>(), s.hi.head<2>(), g.plot.w, g.plot.h);
    const Eigen::Vector4f ndc(float((px + 0.5 - g.plot.x) / g.plot.w * 2 - 1),
                              float(1 - (py + 0.5 - g.plot.y) / g.plot.h * 2), 0.f, 1.f);
    const Eigen::Vector4f w = v.view_proj().inverse() * ndc;
    return {w.x(), w.y()};
  }
};

// Reference for the shader's bilinear mode: weights of the four surrounding bin centres
// (clamped at the edges), renormalised over the valid, finite bins only.
double bilinear_valid(const core::ScalarField& f, const Vec2& p) {
  const auto& g = f.grid;
  const double qx = (p.x() - g.lo.x()) / g.dx() - 0.5, qy = (p.y() - g.lo.y()) / g.dy() - 0.5;
  const int i0 = int(std::floor(qx)), j0 = int(std::floor(qy));
  const double fx = qx - i0, fy = qy - j0;
  double sw = 0, sv = 0;
  for (int dy = 0; dy <= 1; ++dy)
    for (int dx = 0; dx <= 1; ++dx) {
      const int i = std::clamp(i0 + dx, 0, g.nx - 1), j = std::clamp(j0 + dy, 0, g.ny - 1);
      const double v = f.at(i, j);
      if (!f.valid(i, j) || !std::isfinite(v)) continue;
      const double w = (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy);
      sw += w;
      sv += w * std::clamp(v, -1.0, 2.0);
    }
  return sv / sw;
}

TEST_P(FieldRender, MaskedAndNonFiniteBinsAreExactlyNeutral) {
  core::ScalarField f(grid(16, 10));
  for (int iy = 0; iy < 10; ++iy)
    for (int ix = 0; ix < 16; ++ix) f.at(ix, iy) = (ix + iy) % 2 ? 0.9 : 0.1;  // checkerboard: worst case to smear
  f.mask[f.grid.index(4, 4)] = 0;
  f.at(4, 4) = 1e30;  // masked: its value must be ignored
  f.at(8, 4) = std::nan("");
  f.at(11, 6) = std::numeric_limits<double>::infinity();
  f.at(12, 6) = -std::numeric_limits<double>::infinity();
  f.at(2, 7) = 1e300;  // finite but huge: clamped, valid
  const Rgba8 nan = to_rgba8(Colormap::kNanColour);
  const Colormap map(ColormapId::viridis);
  for (FieldFilter filter : {FieldFilter::nearest, FieldFilter::bilinear}) {
    SinglePanel sp(f, filter);
    FrameRenderer r(*ctx_, 400, 300);
    const Image& img = r.render(sp.s, {}, sp.layout);
    const double dx = f.grid.dx(), dy = f.grid.dy();
    for (auto [ix, iy] : {std::pair{4, 4}, {8, 4}, {11, 6}, {12, 6}})
      // Every pixel inside the bad bin (inset by 1.5 px from its edges).
      for (double fx = 0.1; fx <= 0.9; fx += 0.1)
        for (double fy = 0.1; fy <= 0.9; fy += 0.1) {
          const auto [px, py] = sp.pixel({(ix + fx) * dx, (iy + fy) * dy}, 400, 300);
          const auto* c = img.pixel(px, py);
          ASSERT_EQ(c[0], nan.r) << "bin " << ix << "," << iy << " filter " << int(filter);
          ASSERT_EQ(c[1], nan.g);
          ASSERT_EQ(c[2], nan.b);
        }
    // Valid neighbours keep their own colour at their centre: no grey, no masked value.
    for (auto [ix, iy] : {std::pair{3, 4}, {5, 4}, {4, 3}, {4, 5}, {7, 4}, {9, 4}, {10, 6}, {13, 6}, {2, 7}}) {
      const auto [px, py] = sp.pixel(f.grid.centre(ix, iy), 400, 300);
      const double t = filter == FieldFilter::nearest ? f.at(ix, iy) : bilinear_valid(f, sp.world(px, py, 400, 300));
      const Rgba8 want = map.rgba8(std::clamp(t, 0.0, 1.0));
      const auto* c = img.pixel(px, py);
      EXPECT_NEAR(c[0], want.r, 3) << "bin " << ix << "," << iy << " filter " << int(filter);
      EXPECT_NEAR(c[1], want.g, 3);
      EXPECT_NEAR(c[2], want.b, 3);
    }
  }
}

TEST_P(FieldRender, ConstantAndEmptyFieldsRenderWithSensibleRange) {
  core::ScalarField f(grid(12, 8), 3.0);
  const auto range = resolve_range(f, FieldRange{});
  EXPECT_DOUBLE_EQ(range.first, 2.85);
  EXPECT_DOUBLE_EQ(range.second, 3.15);
  const auto ticks = nice_ticks(range.first, range.second, 5);
  ASSERT_GE(ticks.size(), 3u);
  EXPECT_NE(std::find(ticks.begin(), ticks.end(), 3.0), ticks.end());
  // Rendered with the automatic range: the map's middle colour everywhere.
  SinglePanel sp(f, FieldFilter::bilinear);
  sp.layout.panels[0].range = FieldRange::percentile(2, 98);
  sp.layout.panels[0].colour_bar = true;
  FrameRenderer r(*ctx_, 400, 300);
  const Image& img = r.render(sp.s, {}, sp.layout);
  const auto [px, py] = sp.pixel({4.0, 2.5}, 400, 300);
  const Rgba8 mid = Colormap(ColormapId::viridis).rgba8(0.5);
  EXPECT_NEAR(img.pixel(px, py)[0], mid.r, 3);
  EXPECT_NEAR(img.pixel(px, py)[1], mid.g, 3);
  EXPECT_NEAR(img.pixel(px, py)[2], mid.b, 3);
  // All bins masked, and zero everywhere: no crash, neutral / mid colour.
  core::ScalarField none(grid(12, 8), 0.0);
  std::fill(none.mask.begin(), none.mask.end(), 0);
  EXPECT_EQ(resolve_range(none, FieldRange{}), (std::pair{0.0, 1.0}));
  EXPECT_EQ(resolve_range(core::ScalarField(grid(12, 8), 0.0), FieldRange{}), (std::pair{-0.5, 0.5}));
  SinglePanel empty(none, FieldFilter::bilinear);
  const Image& img2 = r.render(empty.s, {}, empty.layout);
  EXPECT_EQ(img2.pixel(px, py)[0], to_rgba8(Colormap::kNanColour).r);
}

TEST_P(FieldRender, TitlesAndCaptionPutInkWhereExpected) {
  FrameRenderer r(*ctx_, 640, 400);
  const Snapshot s = field_scene();
  const FrameLayout l = layout_2x2();
  const Image& img = r.render(s, {}, l);
  const FrameGeometry g = layout_frame(l, 640, 400, true);
  auto dark_pixels = [&](const PixelRect& rect) {
    int n = 0;
    for (int y = rect.y; y < rect.bottom(); ++y)
      for (int x = rect.x; x < rect.right(); ++x) n += img.pixel(x, y)[0] < 100 ? 1 : 0;
    return n;
  };
  for (const auto& p : g.panels) EXPECT_GT(dark_pixels(p.title), 20);  // a title in every strip
  EXPECT_GT(dark_pixels(g.caption), 100);
}

// A caption wider than the frame (a long scene title, then the run's figures) is drawn
// smaller, whole, within the margins, instead of being cut off at the right edge.
TEST_P(FieldRender, LongCaptionShrinksToStayInTheFrame) {
  const int w = 1280, h = 720;
  FrameRenderer r(*ctx_, w, h);
  Snapshot s = field_scene();
  const FrameLayout l = layout_2x2();
  const FrameGeometry g = layout_frame(l, w, h, true);
  s.caption = "x";
  const Image one_letter = r.render(s, {}, l);
  // About 1.2 times the room at the caption's size (16 px here), well within it at 2/3 of that.
  s.caption = "Seed 003 §5 dune, no-slip (tangential flip) obstacle   t = 28200 τ   N = 1439426   τ_E = 240 τ   "
              "U = 0.1   phase = 2 inelastic, r = 0.97   e = 0.97   r_obstacle = 0.97   end";
  const Image caption = r.render(s, {}, l);
  int left = 0, right = 0, margin = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (std::memcmp(one_letter.pixel(x, y), caption.pixel(x, y), 4) != 0) {
        EXPECT_GE(y, g.caption.y);  // nothing else moves
        (x >= w - g.caption_px / 2 ? margin : x < w / 2 ? left : right)++;
      }
  EXPECT_GT(left, 300);   // the caption is drawn
  EXPECT_GT(right, 300);  // across the frame
  EXPECT_EQ(margin, 0);   // and ends inside the right margin
}

TEST_P(FieldRender, ThreeDimensionalSnapshotShowsXyFields) {
  Snapshot s = field_scene();
  s.dim = 3;
  s.hi.z() = 1;
  for (std::size_t i = 0; i < s.size(); ++i) s.pos_radius[4 * i + 2] = 0.5f;
  FrameRenderer r(*ctx_, 320, 200, 4);
  EXPECT_NO_THROW(r.render(s, {}, layout_2x2()));
}

// The README's default scene in miniature: a 200 × 100 stream past an obstacle of radius
// 12 at (60, 50), binned 40 × 20 (bins of 5): a density bump upstream, a warm wake, the
// potential flow's speed; the bins whose centre the obstacle covers are masked (no gas),
// as the ED runner masks them. The masked bins' squares poke out of the round obstacle.
constexpr double kObX = 60, kObY = 50, kObR = 12, kObU = 0.2;
Snapshot obstacle_scene(bool uniform = false) {
  Snapshot s;
  s.dim = 2;
  s.lo = {0, 0, 0};
  s.hi = {200, 100, 0};
  s.obstacles.push_back({{kObX, kObY}, kObR});
  core::GridGeometry g;
  g.nx = 40;
  g.ny = 20;
  g.lo = Vec2(0, 0);
  g.hi = Vec2(200, 100);
  core::ScalarField density(g), temperature(g), speed(g);
  core::VectorField velocity(g);
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) {
      const Vec2 c = g.centre(ix, iy);
      const auto k = g.index(ix, iy);
      const Vec2 p = (c - Vec2(kObX, kObY)) / kObR;
      const double r2 = p.squaredNorm(), r4 = r2 * r2;
      const Vec2 v = kObU * Vec2(1.0 - (p.x() * p.x() - p.y() * p.y()) / r4, -2.0 * p.x() * p.y() / r4);
      density.values[k] = uniform ? 0.8 : 0.8 + 0.08 * std::exp(-(c - Vec2(44, 50)).squaredNorm() / 60.0);
      temperature.values[k] =
          uniform ? 0.025 : 0.02 + 0.012 * std::exp(-std::pow((c.x() - 90) / 30, 2) - std::pow((c.y() - 50) / 9, 2));
      speed.values[k] = std::sqrt(v.squaredNorm() + 2 * temperature.values[k]);
      velocity.values[k] = v;
      if (r2 < 1.0) {
        density.mask[k] = temperature.mask[k] = speed.mask[k] = velocity.mask[k] = 0;
        density.values[k] = temperature.values[k] = speed.values[k] = std::nan("");
        velocity.values[k] = Vec2(std::nan(""), std::nan(""));
      }
    }
  s.fields.push_back({"density", "n [1/σ²]", density});
  s.fields.push_back({"temperature", "kT", temperature});
  s.fields.push_back({"speed", "<|v|>", speed});
  s.velocity = velocity;
  s.reference_velocity = Eigen::Vector2d(kObU, 0.0);
  s.length_unit = "σ";
  return s;
}

// Outside the round obstacle the maps show the field, not the masked bins' neutral grey:
// on a ring 1 to 2 units outside the circle (the outline is 1.5 px wide, 1 unit ≈ 4 px)
// every pixel has the uniform field's colour, in both filter modes, while a masked bin
// away from the obstacle (no data there) stays exactly neutral. Without filling the
// masked bins under the obstacle the corners of the 12 masked bins poke out of it as
// grey squares (on this ring at every diagonal).
TEST_P(FieldRender, MapsMeetARoundObstacleWithoutSquareTeeth) {
  Snapshot s = obstacle_scene(true);
  auto& t = s.fields[1].field;
  const auto far = t.grid.index(35, 3);  // an empty bin far from the obstacle
  t.mask[far] = 0;
  t.values[far] = std::nan("");
  FrameLayout l = make_layout(1, 1, std::vector<std::string>{"temperature"});
  l.caption = false;
  l.panels[0].colour_bar = false;
  l.panels[0].range = FieldRange::fixed(0.0, 0.05);  // the field 0.025 is the map's middle
  l.panels[0].colormap = Colormap(ColormapId::viridis);
  const Rgba8 want = Colormap(ColormapId::viridis).rgba8(0.5), nan = to_rgba8(Colormap::kNanColour);
  const int w = 800, h = 440;
  const auto geo = layout_frame(l, w, h, false).panels[0];
  const ViewTransform v = fit_2d(s.lo.head<2>(), s.hi.head<2>(), geo.plot.w, geo.plot.h);
  auto pixel = [&](const Vec2& p) {
    const Eigen::Vector4f c = v.view_proj() * Eigen::Vector4f(float(p.x()), float(p.y()), 0.f, 1.f);
    return std::pair{int(geo.plot.x + (c.x() + 1) * 0.5 * geo.plot.w), int(geo.plot.y + (1 - c.y()) * 0.5 * geo.plot.h)};
  };
  for (FieldFilter filter : {FieldFilter::nearest, FieldFilter::bilinear}) {
    l.panels[0].filter = filter;
    FrameRenderer r(*ctx_, w, h);
    const Image& img = r.render(s, {}, l);
    int grey = 0, off = 0;
    for (double dr : {1.0, 1.5, 2.0})
      for (int deg = 0; deg < 360; ++deg) {
        const double a = deg * std::numbers::pi / 180;
        const auto [px, py] = pixel(Vec2(kObX, kObY) + (kObR + dr) * Vec2(std::cos(a), std::sin(a)));
        const auto* c = img.pixel(px, py);
        grey += c[0] == nan.r && c[1] == nan.g && c[2] == nan.b;
        off += std::abs(c[0] - want.r) > 3 || std::abs(c[1] - want.g) > 3 || std::abs(c[2] - want.b) > 3;
      }
    EXPECT_EQ(grey, 0) << "filter " << int(filter);
    EXPECT_EQ(off, 0) << "filter " << int(filter);
    const auto [fx, fy] = pixel(t.grid.centre(35, 3));
    EXPECT_EQ(img.pixel(fx, fy)[0], nan.r) << "filter " << int(filter);
    EXPECT_EQ(img.pixel(fx, fy)[1], nan.g);
  }
}

// Values beyond a fixed range are drawn in the end colours and marked by a triangle at
// that end of the bar: one bin above the range adds ink above the bar only, one below it
// ink below the bar only (the map changes at that bin alone, far left of the bar).
TEST_P(FieldRender, ClippedValuesPutATriangleOnTheirEndOfTheBar) {
  core::ScalarField f(grid(16, 10), 0.5);
  auto bar_diff = [&](double value) {
    core::ScalarField g = f;
    g.at(1, 5) = value;
    SinglePanel base(f, FieldFilter::nearest), changed(g, FieldFilter::nearest);
    base.layout.panels[0].colour_bar = changed.layout.panels[0].colour_bar = true;
    FrameRenderer r(*ctx_, 400, 300);
    const Image a = r.render(base.s, {}, base.layout);
    const Image& b = r.render(changed.s, {}, changed.layout);
    const int right = base.pixel(f.grid.hi, 400, 300).first + 2;  // right of the map
    std::pair<int, int> rows{300, -1};                             // first and last row that changed
    for (int y = 0; y < 300; ++y)
      for (int x = right; x < 400; ++x)
        if (std::memcmp(a.pixel(x, y), b.pixel(x, y), 4) != 0) rows = {std::min(rows.first, y), std::max(rows.second, y)};
    return rows;
  };
  const auto [top_bar, bottom_bar] = [&] {  // the map's top and bottom rows: the bar spans them
    SinglePanel sp(f, FieldFilter::nearest);
    return std::pair{sp.pixel({0, 5}, 400, 300).second, sp.pixel({0, 0}, 400, 300).second};
  }();
  const auto above = bar_diff(1.5), below = bar_diff(-0.5), inside = bar_diff(0.9);
  EXPECT_EQ(inside.second, -1);  // within the range: the bar does not change
  ASSERT_GE(above.second, 0);
  ASSERT_GE(below.second, 0);
  EXPECT_LT(above.second, top_bar + (bottom_bar - top_bar) / 4) << "above: rows " << above.first << "–" << above.second;
  EXPECT_GT(below.first, bottom_bar - (bottom_bar - top_bar) / 4) << "below: rows " << below.first << "–" << below.second;
}

// Before the first exposure a map panel draws the geometry — obstacle, piston and filter
// planes — and says when its field comes; with fields the planes are drawn over the map.
TEST_P(FieldRender, PanelsDrawTheGeometryAndSayWhenFieldsCome) {
  Snapshot s = obstacle_scene(true);
  s.boundary_lines.push_back({{197, 0}, {197, 100}});  // the outlet filter
  FrameLayout l = make_layout(1, 1, std::vector<std::string>{"temperature"});
  l.caption = false;
  l.panels[0].colour_bar = false;
  l.panels[0].range = FieldRange::fixed(0.0, 0.05);
  const int w = 800, h = 440;
  const auto geo = layout_frame(l, w, h, false).panels[0];
  const ViewTransform v = fit_2d(s.lo.head<2>(), s.hi.head<2>(), geo.plot.w, geo.plot.h);
  auto pixel = [&](const Vec2& p) {
    const Eigen::Vector4f c = v.view_proj() * Eigen::Vector4f(float(p.x()), float(p.y()), 0.f, 1.f);
    return std::pair{int(geo.plot.x + (c.x() + 1) * 0.5 * geo.plot.w), int(geo.plot.y + (1 - c.y()) * 0.5 * geo.plot.h)};
  };
  auto dark_on_filter = [&](const Image& img) {  // rows along x = 197 whose pixel there is dark
    int n = 0;
    for (double y = 10; y <= 90; y += 10) {
      const auto [px, py] = pixel({197, y});
      int darkest = 255;
      for (int dx = -1; dx <= 1; ++dx) darkest = std::min<int>(darkest, img.pixel(px + dx, py)[0]);
      n += darkest < 80;
    }
    return n;
  };
  FrameRenderer r(*ctx_, w, h);
  const Image with_fields = r.render(s, {}, l);
  EXPECT_EQ(dark_on_filter(with_fields), 9);
  const Rgba8 map_colour = Colormap(ColormapId::inferno).rgba8(0.5);
  const auto [mx, my] = pixel({150, 20});
  EXPECT_NEAR(with_fields.pixel(mx, my)[0], map_colour.r, 3);
  s.fields.clear();
  s.velocity.reset();
  s.fields_pending = "fields from t = 24 (first exposure)";
  const Image pending = r.render(s, {}, l);
  EXPECT_EQ(dark_on_filter(pending), 9);
  const auto [ox, oy] = pixel({kObX, kObY});  // the obstacle, filled
  EXPECT_EQ(pending.pixel(ox, oy)[0], with_fields.pixel(ox, oy)[0]);
  EXPECT_NE(pending.pixel(mx, my)[0], map_colour.r);  // no map
  // The sentence, centred in the plot (right of the obstacle's outline): ink there, and
  // another sentence than without one.
  int ink = 0;
  for (int y = geo.plot.y + geo.plot.h / 2 - 8; y < geo.plot.y + geo.plot.h / 2 + 8; ++y)
    for (int x = pixel({80, 0}).first; x < geo.plot.x + 3 * geo.plot.w / 4; ++x) ink += pending.pixel(x, y)[0] < 100;
  EXPECT_GT(ink, 50);
  s.fields_pending.clear();
  EXPECT_NE(r.render(s, {}, l).rgba, pending.rgba);  // "no temperature field" instead
}

// The default scene's view in miniature with fixed colour ranges ([render.ranges]): the
// maps meet the round obstacle cleanly, the bars keep the given ranges, the flow-speed
// map carries the streamlines. Thresholds as for fields_2x2 (text, streamline edges).
TEST_P(FieldRender, ObstaclePanelsWithFixedRangesMatchGolden) {
  const std::vector<std::string> names = {"density", "temperature", "speed", "streamlines"};
  FrameLayout l = make_layout(2, 2, names);
  const std::vector<std::pair<double, double>> fixed = {{0.75, 0.9}, {0.015, 0.035}, {0.15, 0.35}, {0.0, 0.4}};
  for (std::size_t i = 0; i < fixed.size(); ++i) {
    l.panels[i].range = FieldRange::fixed(fixed[i].first, fixed[i].second);
    l.panels[i].filter = FieldFilter::bilinear;
  }
  l.panels[3].streamlines.trace.separation = 8.0;
  Snapshot s = obstacle_scene();
  s.caption = "obstacle, fixed ranges";
  FrameRenderer r(*ctx_, 640, 400);
  const Image& img = r.render(s, FrameStyle{}, l);
  ASSERT_EQ(r.last_panel_ranges().size(), fixed.size());
  for (std::size_t i = 0; i < fixed.size(); ++i) {
    ASSERT_TRUE(r.last_panel_ranges()[i].has_value()) << i;
    EXPECT_EQ(*r.last_panel_ranges()[i], fixed[i]) << i;
  }
  golden::check_golden(img, "fields_obstacle_fixed", {kMaxChannel, kMaxFraction});
}

// A small 3D bed as the DEM engine draws it: five jittered layers of spheres (radius 0.5 in
// a 10 × 6 × 8 box) coloured by height, periodic in x (dashed edges), walls in y and at
// the bottom (solid edges, the walls behind the bed hatched), open at the top; beside it
// the solid fraction binned on the x–z plane across the whole y depth (bins two diameters
// wide), and a caption with the time in seconds.
Snapshot bed_scene() {
  Snapshot s;
  s.dim = 3;
  s.lo = {0, 0, 0};
  s.hi = {10, 6, 8};
  s.periodic = {true, false, false};
  s.open_faces = {false, false, false, false, false, true};
  core::Rng rng(11);
  std::vector<Vec3> x;
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 6; ++j)
      for (int i = 0; i < 10; ++i) {
        const double px = 0.5 + i + 0.5 * ((j + k) % 2) + 0.08 * rng.uniform(-1, 1);
        const double py = 0.55 + j * 0.98 + 0.04 * rng.uniform(-1, 1);
        const double pz = 0.5 + k * 0.86 + 0.05 * rng.uniform(0, 1);
        if (py > 5.5 || (k == 4 && rng.uniform() < 0.4)) continue;
        x.emplace_back(std::fmod(px, 10.0), py, pz);
      }
  for (const Vec3& p : x) {
    s.pos_radius.insert(s.pos_radius.end(), {float(p.x()), float(p.y()), float(p.z()), 0.5f});
    s.attribute.push_back(float(p.z()));
  }
  s.attribute_name = "height";
  s.time = 0.5;
  s.time_unit = "s";
  s.length_unit = "m";
  s.labels = {{"t", "0.5 s"}, {"N", std::to_string(s.size())}};
  std::vector<Vec3> v(x.size(), Vec3::Zero());
  std::vector<double> r(x.size(), 0.5);
  core::BinAccumulator acc(core::plane_binning(core::BinPlane::xz, s.lo, s.hi, {5, 4}));
  acc.add(std::span<const Vec3>(x), std::span<const Vec3>(v), std::span<const double>(r), {}, s.hi.y() - s.lo.y());
  s.fields.push_back({"fraction", "solid fraction", acc.fraction()});
  return s;
}

TEST_P(FieldRender, ThreeDimensionalBedMatchesGolden) {
  FrameRenderer r(*ctx_, 480, 300, 4);
  FrameStyle style;
  style.colormap = Colormap(ColormapId::viridis);
  style.range = std::pair{0.0, 4.5};
  const std::vector<std::string> names = {"particles", "fraction"};
  FrameLayout l = make_layout(2, 1, names);
  set_fixed_range(l, "fraction", 0.0, 0.6);
  golden::check_golden(r.render(bed_scene(), style, l), "bed_3d", {kMaxChannel, kMaxFraction});
}

// Walls and periodic faces read apart (no GL needed: the segments themselves).
// A long "fields pending" message stays within its panel: dem_freefall_box's frame 0 at
// its render size (1440 × 600, three panels 480 px wide) said "fields from the next frame
// (averaged since this one)" on one line ≈ 530 px wide, over the panel beside it. Every
// pixel the message changes (against a one-letter one) lies in its own panel.
TEST_P(FieldRender, PendingMessageStaysWithinItsPanel) {
  Snapshot s = bed_scene();
  s.fields.clear();
  s.velocity.reset();
  // The map on the right: its plot sits left of its colour-bar room, so a message too
  // wide for it runs out on the left, over the particles.
  FrameLayout l = make_layout(2, 1, std::vector<std::string>{"particles", "fraction"});
  l.caption = false;
  const int w = 960, h = 600;
  const PanelGeometry g = layout_frame(l, w, h, false).panels[1];
  ASSERT_EQ(g.panel.x, 480);
  FrameRenderer r(*ctx_, w, h, 0);
  s.fields_pending = "x";
  const Image one_letter = r.render(s, {}, l);
  s.fields_pending = "fields from the next frame (averaged since this one)";
  const Image message = r.render(s, {}, l);
  int inside = 0, outside = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (std::memcmp(one_letter.pixel(x, y), message.pixel(x, y), 4) != 0) (x >= g.panel.x ? inside : outside)++;
  EXPECT_GT(inside, 300);  // the message is drawn
  EXPECT_EQ(outside, 0);
}

TEST(BoxFaces, WallEdgesSolidPeriodicEdgesDashedWallsBehindHatched) {
  const Eigen::Vector3d lo(0, 0, 0), hi(1, 1, 1), eye(10, 10, 10);  // eye beyond the hi corner
  auto count = [](const std::vector<Segment>& segs, float alpha) {
    return std::count_if(segs.begin(), segs.end(), [&](const Segment& g) { return g.rgba[3] == alpha; });
  };
  std::vector<Segment> periodic;
  add_box(periodic, lo, hi, {BoxFace::periodic, BoxFace::periodic, BoxFace::periodic, BoxFace::periodic,
                             BoxFace::periodic, BoxFace::periodic}, eye, {0, 0, 0}, 2.0f);
  EXPECT_EQ(count(periodic, 1.0f), 0);       // no solid edge
  EXPECT_EQ(count(periodic, 0.6f), 12 * 12);  // 12 edges of 12 dashes
  std::vector<Segment> walls;
  add_box(walls, lo, hi, {BoxFace::wall, BoxFace::wall, BoxFace::wall, BoxFace::wall, BoxFace::wall, BoxFace::wall},
          eye, {0, 0, 0}, 2.0f);
  EXPECT_EQ(count(walls, 1.0f), 12);
  EXPECT_EQ(count(walls, 0.6f), 0);
  // Hatched: the three lo faces, whose inner sides face the eye; 31 diagonals each.
  EXPECT_EQ(count(walls, 0.3f), 3 * 31);
  for (const Segment& g : walls) {
    if (g.rgba[3] != 0.3f) continue;
    EXPECT_TRUE(g.p0[0] == 0.f || g.p0[1] == 0.f || g.p0[2] == 0.f);
  }
  // Periodic in x and y, walls in z (a sheared bed): vertical edges dashed, the rest solid.
  std::vector<Segment> bed;
  add_box(bed, lo, hi, {BoxFace::periodic, BoxFace::periodic, BoxFace::periodic, BoxFace::periodic, BoxFace::wall,
                        BoxFace::wall}, eye, {0, 0, 0}, 2.0f);
  EXPECT_EQ(count(bed, 1.0f), 8);
  EXPECT_EQ(count(bed, 0.6f), 4 * 12);
  EXPECT_EQ(count(bed, 0.3f), 31);  // the floor, seen from above
}

INSTANTIATE_TEST_SUITE_P(Backends, FieldRender, ::testing::Values(Backend::Egl, Backend::OSMesa),
                         [](const auto& info) { return std::string(backend_name(info.param)); });

// The binary draws with the shaders in assets/shaders/, as they are now: the build embeds
// them, and re-embeds one that was edited. (An edited shader once stayed out of the binary
// — CMake read the files but did not watch them — so a fix in it changed no picture.)
TEST(EmbeddedShaders, AreTheFilesInAssetsAsTheyAreNow) {
  const fs::path dir = fs::path(GRAINFLOW_GOLDEN_DIR).parent_path().parent_path() / "assets" / "shaders";
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    std::ifstream in(entry.path(), std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(shader_source(entry.path().filename().string()), text) << entry.path().filename();
    ++files;
  }
  EXPECT_EQ(files, embedded_shaders().size());
}

// The masked bins whose square reaches into a solid circle take the mean of their valid
// neighbours, pass after pass, and are drawn; other masked bins keep their mask.
TEST(FieldMap, MaskedBinsUnderASolidTakeTheirNeighboursMean) {
  core::GridGeometry g;
  g.nx = g.ny = 10;
  g.lo = Vec2(0, 0);
  g.hi = Vec2(10, 10);
  std::vector<float> v(g.size());
  std::vector<std::uint8_t> ok(g.size(), 1);
  for (int iy = 0; iy < 10; ++iy)
    for (int ix = 0; ix < 10; ++ix) v[g.index(ix, iy)] = float(ix + 10 * iy);
  const SolidCircle c{Vec2(5, 5), 2.2};
  // Masked: the bins whose centre the circle covers (the 4 × 4 block 3…6), and two others.
  std::vector<std::size_t> under;
  for (int iy = 0; iy < 10; ++iy)
    for (int ix = 0; ix < 10; ++ix)
      if ((g.centre(ix, iy) - c.centre).norm() < c.radius) ok[g.index(ix, iy)] = 0, under.push_back(g.index(ix, iy));
  ASSERT_EQ(under.size(), 16u);
  ok[g.index(0, 9)] = 0;
  ok[g.index(1, 5)] = 0;  // masked next to the circle's bins, its square not reaching it
  std::vector<float> filled = v;
  std::vector<std::uint8_t> filled_ok = ok;
  fill_bins_under_solids(g, filled, filled_ok, std::span<const SolidCircle>(&c, 1));
  for (std::size_t b : under) EXPECT_EQ(filled_ok[b], 1) << b;
  EXPECT_EQ(filled_ok[g.index(0, 9)], 0);
  EXPECT_EQ(filled_ok[g.index(1, 5)], 0);
  // First pass: bin (3, 4) sees (2, 3), (2, 4), (2, 5) valid, the rest of its 3 × 3 masked.
  EXPECT_FLOAT_EQ(filled[g.index(3, 4)], (32.f + 42.f + 52.f) / 3.f);
  // Second pass: the four middle bins have no valid neighbour at first; (4, 4) then sees
  // the first pass's ring bins (3, 3), (4, 3), (5, 3), (3, 4), (3, 5), not its fellows.
  std::vector<float> ring;
  for (auto [jx, jy] : {std::pair{3, 3}, {4, 3}, {5, 3}, {3, 4}, {3, 5}})
    ring.push_back(filled[g.index(jx, jy)]);
  EXPECT_FLOAT_EQ(filled[g.index(4, 4)], (ring[0] + ring[1] + ring[2] + ring[3] + ring[4]) / 5.f);
  // Valid bins are untouched; without solids nothing changes.
  for (std::size_t b = 0; b < g.size(); ++b) {
    if (ok[b]) {
      EXPECT_EQ(filled[b], v[b]);
    }
  }
  std::vector<float> same = v;
  std::vector<std::uint8_t> same_ok = ok;
  fill_bins_under_solids(g, same, same_ok, {});
  EXPECT_EQ(same_ok, ok);
}

TEST(ColourBarTicks, NiceSteps) {
  EXPECT_EQ(nice_ticks(0.0, 1.0, 5), (std::vector<double>{0.0, 0.2, 0.4, 0.6000000000000001, 0.8, 1.0}));
  const auto t = nice_ticks(-0.013, 0.042, 5);
  ASSERT_FALSE(t.empty());
  EXPECT_DOUBLE_EQ(tick_step(t), 0.01);
  EXPECT_EQ(t.front(), -0.01);
  EXPECT_DOUBLE_EQ(t.back(), 0.04);
  EXPECT_EQ(nice_ticks(1.0, 1.0, 5).size(), 0u);
  EXPECT_EQ(nice_ticks(0.0, std::nan(""), 5).size(), 0u);
  EXPECT_DOUBLE_EQ(tick_step(nice_ticks(0, 7, 4)), 2.0);
  EXPECT_DOUBLE_EQ(tick_step(nice_ticks(0, 430, 5)), 100.0);
  EXPECT_EQ(format_tick(0.25, 0.05), "0.25");
  EXPECT_EQ(format_tick(120, 20), "120");
  EXPECT_EQ(format_tick(-0.0, 0.1), "0.0");
  EXPECT_EQ(format_tick(1.5e6, 5e5), "1.5e+06");
  EXPECT_EQ(format_tick(0.012, 0.002), "0.012");
}

TEST(FieldRange, PercentileIgnoresOneHotBin) {
  core::ScalarField f(grid(10, 10));
  for (std::size_t i = 0; i < f.values.size(); ++i) f.values[i] = double(i % 10);  // 0..9
  f.values[55] = 1e6;  // one hot bin
  f.values[56] = std::nan("");
  f.mask[57] = 0;
  f.values[57] = -1e9;  // masked: ignored
  const auto automatic = resolve_range(f, FieldRange{});
  EXPECT_EQ(automatic.second, 1e6);
  const auto p = resolve_range(f, FieldRange::percentile(2, 98));
  EXPECT_DOUBLE_EQ(p.first, 0.0);
  EXPECT_DOUBLE_EQ(p.second, 9.0);
  EXPECT_THROW(resolve_range(f, FieldRange::fixed(1, 1)), Error);
  EXPECT_THROW(resolve_range(f, FieldRange::percentile(50, 20)), Error);
}

TEST(PanelLayout, NamesAndGeometry) {
  EXPECT_EQ(panel_names().size(), 8u);
  for (auto n : panel_names()) EXPECT_NO_THROW(panel_from_name(n));
  try {
    panel_from_name("nonsense");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("nonsense"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("particles, density, fraction, temperature, speed, vorticity, streamlines, velocity"),
              std::string::npos);
  }
  const std::vector<std::string> five(5, "density");
  EXPECT_THROW(make_layout(2, 2, five), Error);
  EXPECT_THROW(make_layout(0, 2, {}), Error);
  // 3 × 2 cells tile 1001 × 601 exactly (odd sizes included), caption at the bottom.
  FrameLayout l = make_layout(3, 2, {});
  const FrameGeometry g = layout_frame(l, 1001, 601, true);
  ASSERT_EQ(g.panels.size(), 6u);
  long area = 0;
  for (const auto& p : g.panels) area += long(p.panel.w) * p.panel.h;
  EXPECT_EQ(area + long(g.caption.w) * g.caption.h, 1001L * 601L);
  EXPECT_EQ(g.caption.bottom(), 601);
  EXPECT_EQ(g.panels[5].panel.right(), 1001);
}

// Without render.layout the grid is the one that draws the domain largest: a 2:1 stream in
// a 16:9 frame fills a 2 × 2 grid, a 4:1 stream stacks its panels, a tall box lines them
// up; three panels of a square box at 16:9 go in one row rather than a 2 × 2 grid with a
// hole. The chosen grid is never beaten by another one.
TEST(PanelLayout, FittedGridDrawsTheDomainLargest) {
  auto fitted_area = [](int cols, int rows, int w, int h, double aspect) {
    FrameLayout l;
    l.cols = cols;
    l.rows = rows;
    const PixelRect p = layout_frame(l, w, h, true).panels.front().plot;
    const double x = std::min<double>(p.w, p.h * aspect);
    return x * x / aspect;
  };
  EXPECT_EQ(fitted_grid(4, 1280, 720, 2.0, true), std::make_pair(2, 2));
  EXPECT_EQ(fitted_grid(4, 1280, 720, 4.0, true), std::make_pair(1, 4));
  EXPECT_EQ(fitted_grid(4, 1280, 720, 0.25, true), std::make_pair(4, 1));
  EXPECT_EQ(fitted_grid(3, 1920, 1080, 1.0, true), std::make_pair(3, 1));
  EXPECT_EQ(fitted_grid(1, 640, 480, 1.0, true), std::make_pair(1, 1));
  for (double aspect : {0.3, 1.0, 2.0, 3.0, 6.0})
    for (int n : {1, 2, 3, 4, 5, 6}) {
      const auto [c, r] = fitted_grid(n, 1920, 1080, aspect, true);
      ASSERT_GE(c * r, n);
      for (int cols = 1; cols <= n; ++cols)
        EXPECT_GE(fitted_area(c, r, 1920, 1080, aspect) * 1.011, fitted_area(cols, (n + cols - 1) / cols, 1920, 1080, aspect))
            << n << " panels, aspect " << aspect << ": " << c << " × " << r << " against " << cols << " columns";
    }
}

// Text fitted to a width (the panels' messages): broken at spaces into the fewest lines,
// as even as that count allows, and smaller only when max_lines cannot hold it. Measured
// here as monospace: half the font size per character.
TEST(FitText, BreaksAtSpacesEvenlyAndShrinksOnlyIfItMust) {
  const auto mono = [](std::string_view t, int px) { return 0.5f * float(px) * float(t.size()); };
  const std::string msg = "fields from the next frame (averaged since this one)";  // 52 characters: 260 px at 10 px
  FittedText one = fit_text("abc def", 100, 10, 3, mono);
  EXPECT_EQ(one.lines, (std::vector<std::string>{"abc def"}));
  EXPECT_EQ(one.px, 10);
  // Two lines of 26 and 25 characters (greedy: 36 and 15).
  FittedText two = fit_text(msg, 200, 10, 3, mono);
  EXPECT_EQ(two.lines, (std::vector<std::string>{"fields from the next frame", "(averaged since this one)"}));
  EXPECT_EQ(two.px, 10);
  for (const auto& line : two.lines) EXPECT_LE(mono(line, two.px), 200.f);
  // One line only: the largest size at which 52 characters fit 200 px is 7 (182 px).
  FittedText shrunk = fit_text(msg, 200, 10, 1, mono);
  EXPECT_EQ(shrunk.lines, (std::vector<std::string>{msg}));
  EXPECT_EQ(shrunk.px, 7);
  // A word wider than the room even at min_px is left as it is, at min_px.
  FittedText wide = fit_text("abcdefghij", 20, 10, 3, mono, 6);
  EXPECT_EQ(wide.lines, (std::vector<std::string>{"abcdefghij"}));
  EXPECT_EQ(wide.px, 6);
  EXPECT_TRUE(fit_text("  ", 20, 10, 3, mono).lines.empty());
}

TEST(Caption, FromLabels) {
  Snapshot s;
  s.labels = {{"t", "1"}, {"U", "0.1"}};
  EXPECT_EQ(caption_text(s), "t = 1     U = 0.1");
  s.caption = "custom";
  EXPECT_EQ(caption_text(s), "custom");
}

TEST(Font, MissingFontIsAClearError) {
  ::setenv("GRAINFLOW_FONT", "/nonexistent/font.ttf", 1);
  try {
    find_default_font();
    ::unsetenv("GRAINFLOW_FONT");
    FAIL();
  } catch (const Error& e) {
    ::unsetenv("GRAINFLOW_FONT");
    EXPECT_NE(std::string(e.what()).find("/nonexistent/font.ttf"), std::string::npos);
  }
  EXPECT_NE(find_default_font().find("DejaVuSans.ttf"), std::string::npos);
}

}  // namespace
