// render/plot: the tick algorithms (linear 1-2-5 steps, log decades with minor ticks and
// their labels), the axis ranges and their errors, and a figure with every feature (two
// series, log axis, error bars, a dashed reference, markers, a legend, title and labels)
// against a golden image on both backends.
//
// Golden threshold: a pixel counts as different when its largest channel differs by more
// than kMaxChannel = 16 levels; at most kMaxFraction = 0.2 % of the pixels (240 of the
// 400 × 300 frame) may differ — as for the field panels (field_render_test.cpp):
// FreeType text and anti-aliased segment edges round differently across FreeType and
// Mesa/LLVM versions. Moving one series by a pixel changes far more (the test below shows
// the comparator notices a changed value). Goldens: Mesa 22.3 llvmpipe, FreeType 2.12.
// GRAINFLOW_UPDATE_GOLDEN=1 rewrites the golden image (commit it with the reason).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "render/image/compare.hpp"
#include "render/plot/plot.hpp"
#include "tests/render/golden_support.hpp"

using namespace grainflow;
using namespace grainflow::render;
using namespace grainflow::render::plot;

namespace {

constexpr int kMaxChannel = 16;
constexpr double kMaxFraction = 0.002;

std::vector<double> values(const std::vector<Tick>& t, bool labelled_only = false) {
  std::vector<double> v;
  for (const auto& x : t)
    if (!labelled_only || !x.label.empty()) v.push_back(x.value);
  return v;
}
std::vector<std::string> labels(const std::vector<Tick>& t) {
  std::vector<std::string> v;
  for (const auto& x : t)
    if (!x.label.empty()) v.push_back(x.label);
  return v;
}

Figure sample_figure() {
  Figure f;
  f.width = 400;
  f.height = 300;
  f.title = "Cooling, r = 0.9";
  f.x = {"t (τ)", true, {}};
  f.y = {"kT", true, {}};
  Series data, law;
  data.label = "measured";
  data.style = SeriesStyle::line_points;
  law.label = "Haff";
  law.dashed = true;
  law.colour = Rgb{0.1f, 0.1f, 0.1f};
  for (int i = 0; i <= 20; ++i) {
    const double t = 0.1 * std::pow(10.0, i / 5.0);  // 0.1 … 1000
    data.x.push_back(t);
    data.y.push_back(0.02 / std::pow(1 + t / 5.0, 2) * (1 + 0.02 * t / (1 + 0.01 * t)));
    data.y_err.push_back(0.1 * data.y.back());
    law.x.push_back(t);
    law.y.push_back(0.02 / std::pow(1 + t / 5.0, 2));
  }
  f.series = {data, law};
  return f;
}

}  // namespace

TEST(PlotTicks, LinearTicksAreNiceStepsInsideTheRange) {
  EXPECT_EQ(values(linear_ticks(0.0, 10.0, 5)), (std::vector<double>{0, 2, 4, 6, 8, 10}));
  EXPECT_EQ(labels(linear_ticks(0.0, 1.0, 4)), (std::vector<std::string>{"0.0", "0.2", "0.4", "0.6", "0.8", "1.0"}));
  const auto t = linear_ticks(-0.013, 0.021, 5);
  ASSERT_GE(t.size(), 3u);
  for (const auto& x : t) {
    EXPECT_GE(x.value, -0.013);
    EXPECT_LE(x.value, 0.021);
  }
  // The step is 1, 2 or 5 × 10^k and zero is exactly zero.
  EXPECT_EQ(labels(linear_ticks(-0.013, 0.021, 5)), (std::vector<std::string>{"-0.010", "-0.005", "0.000", "0.005", "0.010", "0.015", "0.020"}));
  EXPECT_TRUE(linear_ticks(1.0, 1.0, 5).empty());
  EXPECT_TRUE(linear_ticks(0.0, std::numeric_limits<double>::infinity(), 5).empty());
}

TEST(PlotTicks, LogTicksAreDecadesWithMinorTicksBetween) {
  const auto t = log_ticks(1e-6, 1.2e-2);
  EXPECT_EQ(values(t, true), (std::vector<double>{1e-6, 1e-5, 1e-4, 1e-3, 1e-2}));
  EXPECT_EQ(labels(t), (std::vector<std::string>{"10⁻⁶", "10⁻⁵", "10⁻⁴", "10⁻³", "10⁻²"}));
  // Minor ticks at 2..9 × 10^k, unlabelled: 8 per full decade, and none outside.
  int minors = 0;
  for (const auto& x : t) {
    minors += !x.major;
    EXPECT_GE(x.value, 1e-6 * (1 - 1e-9));
    EXPECT_LE(x.value, 1.2e-2 * (1 + 1e-9));
  }
  EXPECT_EQ(minors, 4 * 8);
  // Many decades: every m-th labelled, at most max_labels.
  EXPECT_EQ(labels(log_ticks(1e-12, 1e12, 8)).size(), 7u);  // 10^-12, -8, …, 12 (every 4th)
  EXPECT_EQ(decade_label(0), "10⁰");
  EXPECT_EQ(decade_label(12), "10¹²");
}

TEST(PlotTicks, LogAxesUnderTwoDecadesLabelTheirMinorTicks) {
  // 0.018 … 0.16: one decade inside; the 2 and 5 are labelled, as plain numbers.
  EXPECT_EQ(labels(log_ticks(0.018, 0.16)), (std::vector<std::string>{"0.02", "0.05", "0.1"}));
  // 1 … 30: two decades inside but a span of 1.5: the 2 and 5 are labelled as well.
  EXPECT_EQ(labels(log_ticks(0.9, 32.0)), (std::vector<std::string>{"1", "2", "5", "10", "20"}));
  // Under 0.6 decades: every mantissa.
  EXPECT_EQ(labels(log_ticks(0.15, 0.55)), (std::vector<std::string>{"0.2", "0.3", "0.4", "0.5"}));
  // Under a fifth of a decade: plain linear ticks, never fewer than two labels.
  EXPECT_GE(labels(log_ticks(0.0195, 0.0205)).size(), 2u);
  EXPECT_TRUE(log_ticks(0.0, 1.0).empty());
  EXPECT_TRUE(log_ticks(-1.0, 1.0).empty());
}

TEST(PlotRange, AxisRangesAndTheirErrors) {
  Figure f;
  Series s;
  s.x = {0, 1, 2};
  s.y = {1, 2, 3};
  s.y_err = {0.5, 0.5, 0.5};
  f.series = {s};
  const auto [lo, hi] = axis_range(f, false);
  EXPECT_LT(lo, 0.5);  // error bars are inside, padded
  EXPECT_GT(hi, 3.5);
  f.x.log = true;
  try {
    axis_range(f, true);
    FAIL() << "x = 0 on a log axis was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("point 1 has x = 0"), std::string::npos) << e.what();
  }
  f.x.log = false;
  f.series[0].x = {std::nan(""), std::nan(""), std::nan("")};
  EXPECT_THROW(axis_range(f, true), Error);  // nothing finite
  f.series.clear();
  EXPECT_THROW(axis_range(f, true), Error);
  Figure g;
  g.series = {s};
  g.y.range = std::pair{2.0, 1.0};
  EXPECT_THROW(axis_range(g, false), Error);
}

class PlotRender : public ::testing::TestWithParam<Backend> {
protected:
  void SetUp() override {
    ctx_ = golden::context_or_null(GetParam());
    if (!ctx_) GTEST_SKIP() << "no " << backend_name(GetParam()) << " context on this machine";
  }
  std::unique_ptr<GlContext> ctx_;
};

TEST_P(PlotRender, FigureMatchesGolden) {
  const Image a = draw_figure(*ctx_, sample_figure());
  EXPECT_EQ(a.width, 400);
  EXPECT_EQ(a.height, 300);
  golden::check_golden(a, "plot_loglog", {kMaxChannel, kMaxFraction});
  // The same figure twice: the same pixels.
  const Image b = draw_figure(*ctx_, sample_figure());
  EXPECT_EQ(a.rgba, b.rgba);
  // A changed value is noticed by the comparator at the golden threshold.
  Figure moved = sample_figure();
  for (double& y : moved.series[0].y) y *= 1.5;
  const auto r = compare_images(draw_figure(*ctx_, moved), a, {kMaxChannel, kMaxFraction});
  EXPECT_FALSE(r.passed);
}

TEST_P(PlotRender, BadFiguresAreRefused) {
  Figure f = sample_figure();
  f.series[0].y_err[3] = -1;
  EXPECT_THROW(draw_figure(*ctx_, f), Error);
  f = sample_figure();
  f.series[1].y.pop_back();
  EXPECT_THROW(draw_figure(*ctx_, f), Error);
  f = sample_figure();
  f.width = 10;
  EXPECT_THROW(draw_figure(*ctx_, f), Error);
  f.series.clear();
  f.width = 400;
  EXPECT_THROW(draw_figure(*ctx_, f), Error);
}

INSTANTIATE_TEST_SUITE_P(Backends, PlotRender, ::testing::Values(Backend::Egl, Backend::OSMesa),
                         [](const auto& info) { return std::string(backend_name(info.param)); });
