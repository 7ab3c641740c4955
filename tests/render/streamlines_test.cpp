// Streamline geometry against analytic flows: potential flow past a cylinder (stream
// function conserved), solid-body rotation (closed circles), uniform flow (straight, evenly
// spaced), Jobard–Lefer separation by brute force, and robustness to bad fields.
#include "render/layers/streamlines.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numbers>

#include "engine/core/error.hpp"
#include "engine/core/rng.hpp"
#include "render/layers/streamline_layer.hpp"

using grainflow::Vec2;
using grainflow::core::GridGeometry;
using grainflow::core::VectorField;
using namespace grainflow::render;

namespace {

constexpr double kPi = std::numbers::pi;

// 60×60 bins over [-1, 1]²: bin size h = 1/30, U·L = 2 for U = 1.
GridGeometry square_grid(int n = 60) {
  GridGeometry g;
  g.nx = g.ny = n;
  g.lo = Vec2(-1.0, -1.0);
  g.hi = Vec2(1.0, 1.0);
  return g;
}

VectorField sample_field(const GridGeometry& g, const std::function<Vec2(const Vec2&)>& v) {
  VectorField f(g, Vec2::Zero());
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) f.at(ix, iy) = v(g.centre(ix, iy));
  return f;
}

// Potential flow past a cylinder of radius a, uniform U along x far away.
struct Cylinder {
  double U = 1.0, a = 0.25;
  Vec2 velocity(const Vec2& p) const {
    const double r2 = p.squaredNorm(), r4 = r2 * r2;
    return {U * (1.0 - a * a * (p.x() * p.x() - p.y() * p.y()) / r4), -U * 2.0 * a * a * p.x() * p.y() / r4};
  }
  double psi(const Vec2& p) const { return U * p.y() * (1.0 - a * a / p.squaredNorm()); }
  // |d²v/dx²| = |d²v/dy²| = |w''(z)| = 6 U a² / r⁴ for w = U (1 - a²/z²).
  double second_derivative(double r) const { return 6.0 * U * a * a / std::pow(r, 4); }
};

VectorField cylinder_field(const Cylinder& c, const GridGeometry& g) {
  VectorField f = sample_field(g, [&](const Vec2& p) { return c.velocity(p); });
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix)
      if (g.centre(ix, iy).norm() < c.a) {
        f.mask[g.index(ix, iy)] = 0;
        f.at(ix, iy) = Vec2(std::nan(""), std::nan(""));  // masked data is undefined
      }
  return f;
}

// Smallest distance between vertices of two different lines (brute force).
double min_interline_distance(const std::vector<Streamline>& lines) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t a = 0; a < lines.size(); ++a)
    for (std::size_t b = a + 1; b < lines.size(); ++b)
      for (const auto& p : lines[a].points)
        for (const auto& q : lines[b].points) best = std::min(best, (p.position - q.position).squaredNorm());
  return std::sqrt(best);
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Interpolation

TEST(VelocitySampler, LinearFieldIsExactIncludingBorder) {
  const auto g = square_grid();
  const auto lin = [](const Vec2& p) { return Vec2(0.3 + 2.0 * p.x() - 0.7 * p.y(), -1.1 * p.x() + 0.4 * p.y() - 0.2); };
  const VectorField f = sample_field(g, lin);
  const VelocitySampler s(f, {}, Vec2(0.1, -0.3));
  grainflow::core::Rng rng(7);
  for (int i = 0; i < 2000; ++i) {
    const Vec2 p(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0));  // includes the half-bin border
    Vec2 v;
    ASSERT_TRUE(s.sample(p, v));
    EXPECT_NEAR((v - (lin(p) - Vec2(0.1, -0.3))).norm(), 0.0, 1e-12);
  }
  Vec2 v;
  EXPECT_FALSE(s.sample(Vec2(1.0001, 0.0), v)) << "outside the rectangle is blocked";
}

TEST(VelocitySampler, BilinearBetweenCentresAndBlockedStencils) {
  auto g = square_grid(4);  // bins of 0.5, centres at -0.75, -0.25, 0.25, 0.75
  VectorField f(g, Vec2(1.0, 0.0));
  f.at(1, 1) = Vec2(3.0, 2.0);
  const VelocitySampler s(f, {}, Vec2::Zero());
  Vec2 v;
  ASSERT_TRUE(s.sample(Vec2(-0.5, -0.5), v));  // midway between 4 centres: mean
  EXPECT_NEAR(v.x(), 1.5, 1e-15);
  EXPECT_NEAR(v.y(), 0.5, 1e-15);

  f.at(2, 2) = Vec2(std::numeric_limits<double>::infinity(), 0.0);  // inf = masked
  f.mask[g.index(0, 3)] = 0;
  const SolidCircle solid{Vec2(0.75, -0.75), 0.1};
  const VelocitySampler b(f, {&solid, 1}, Vec2::Zero());
  EXPECT_TRUE(b.blocked(Vec2(0.0, 0.0))) << "stencil (1..2, 1..2) holds the inf bin";
  EXPECT_TRUE(b.blocked(Vec2(0.5, 0.5))) << "stencil (2..3, 2..3) holds the inf bin";
  EXPECT_FALSE(b.blocked(Vec2(-0.5, -0.5)));
  EXPECT_TRUE(b.blocked(Vec2(-0.9, 0.9))) << "border stencil holds the masked bin";
  EXPECT_TRUE(b.blocked(Vec2(0.76, -0.74))) << "inside the solid circle";
  EXPECT_FALSE(b.blocked(Vec2(0.6, -0.6)));
  EXPECT_DOUBLE_EQ(b.max_speed(), std::hypot(3.0, 2.0));
}

// ---------------------------------------------------------------------------------------
// Analytic flows

// Traces the cylinder flow binned on n×n bins; checks every line against its own bound and
// that no vertex enters the cylinder; returns the worst |Δψ| over all lines.
double cylinder_worst_dpsi(int n, double* worst_bound_out = nullptr, std::size_t* nlines = nullptr) {
  const Cylinder cyl;
  const auto g = square_grid(n);
  const VectorField f = cylinder_field(cyl, g);
  const SolidCircle solid{Vec2::Zero(), cyl.a};
  StreamlineOptions o;
  o.separation = 0.06;  // 1.8 bins at n = 60
  const auto lines = trace_streamlines(f, {&solid, 1}, o);
  EXPECT_GE(lines.size(), 25u);
  if (nlines) *nlines = lines.size();

  // Along a traced line dψ/ds = (v × v_h)/|v_h| = (v × e)/|v_h|, e = v_h - v the bilinear
  // error, so |Δψ| <= ∫ |v||e|/(|v| - |e|) ds with |e| <= (h²/8)(|v_xx| + |v_yy|) =
  // (h²/4)·6Ua²/r⁴ inside the grid (r taken at the stencil's nearest corner, r - h/√2),
  // three times that in the half-bin border (linear extrapolation to t = -1/2). The RK4
  // error (step 0.25 bin) is far smaller: the measured worst |Δψ| does not change when the
  // step goes from 0.5 to 0.05 bin (1.0e-4 … 1.2e-4 at n = 60).
  const double h = g.dx();
  double worst = 0.0, worst_bound = 0.0;
  for (const auto& line : lines) {
    const double psi0 = cyl.psi(line.points.front().position);
    double bound = 0.0, dev = 0.0;
    for (std::size_t i = 0; i < line.points.size(); ++i) {
      const Vec2 p = line.points[i].position;
      EXPECT_GE(p.norm(), cyl.a) << "vertex inside the cylinder";
      dev = std::max(dev, std::abs(cyl.psi(p) - psi0));
      if (i > 0) {
        const double ds = line.points[i].arc_length - line.points[i - 1].arc_length;
        const bool border = std::abs(p.x()) > 1.0 - 0.5 * h || std::abs(p.y()) > 1.0 - 0.5 * h;
        const double e = (border ? 3.0 : 1.0) * h * h / 4.0 * cyl.second_derivative(p.norm() - h / std::sqrt(2.0));
        const double vt = cyl.velocity(p).norm();
        bound += ds * vt * e / std::max(vt - e, 1e-3);
      }
    }
    EXPECT_LE(dev, bound + 1e-6) << "line of " << line.points.size() << " points from "
                                 << line.points.front().position.transpose();
    worst = std::max(worst, dev);
    worst_bound = std::max(worst_bound, bound);
  }
  if (worst_bound_out) *worst_bound_out = worst_bound;
  return worst;
}

TEST(Streamlines, PotentialFlowPastCylinderConservesStreamFunction) {
  // The per-line bound above is rigorous but pessimistic (it ignores the cancellation of
  // the error fore and aft of the cylinder; worst bound ≈ 1e-2). The headline criterion:
  // |Δψ| < 0.05% of U·L = 1e-3 on 60×60 bins (measured 1.2e-4; nearest-bin values or a
  // first-order integrator at this step exceed it).
  double bound = 0.0;
  std::size_t n = 0;
  const double worst = cylinder_worst_dpsi(60, &bound, &n);
  EXPECT_LT(worst, 0.0005 * 1.0 * 2.0);
  std::printf("cylinder 60x60: %zu lines, max |dpsi| = %.2e (U L = 2), worst per-line bound %.2e\n", n, worst,
              bound);
}

TEST(Streamlines, StreamFunctionErrorConvergesAsBinSizeSquared) {
  // The error is the bilinear interpolation's, O(h²): halving the bin must cut it by at
  // least 2.5 (4 ideally; measured 3.6 from 30 to 60 bins). O(h) interpolation gives 2.
  const double coarse = cylinder_worst_dpsi(30), fine = cylinder_worst_dpsi(60);
  EXPECT_GT(coarse / fine, 2.5) << "30 bins: " << coarse << ", 60 bins: " << fine;
}

TEST(Streamlines, SolidBodyRotationGivesClosedCircles) {
  const auto g = square_grid();
  const double omega = 0.7;
  const VectorField f = sample_field(g, [&](const Vec2& p) { return Vec2(-omega * p.y(), omega * p.x()); });
  StreamlineOptions o;
  o.separation_fraction = 0.03;
  const auto lines = trace_streamlines(f, {}, o);
  const double step = 0.25 * g.dx();  // below 0.5·d_test = 0.015, so this is the step
  int closed = 0;
  for (const auto& line : lines) {
    double rmin = 1e9, rmax = 0.0;
    for (const auto& p : line.points) {
      rmin = std::min(rmin, p.position.norm());
      rmax = std::max(rmax, p.position.norm());
    }
    if (rmax > 0.97) continue;  // arcs cut by the domain edge
    ++closed;
    EXPECT_TRUE(line.closed) << "circle r = " << rmax;
    // Bilinear interpolation is exact for a linear field, so only RK4 contributes: its
    // amplification on a rotation by θ = step/r per step is 1 - θ⁶/144, i.e. a radial
    // drift of 2π θ⁵/144 per revolution (2× margin below).
    const double theta = step / rmax;
    EXPECT_LT((rmax - rmin) / rmax, 2.0 * 2.0 * kPi * std::pow(theta, 5) / 144.0) << "r = " << rmax;
    const auto& pts = line.points;
    ASSERT_GE(pts.size(), 3u);
    EXPECT_EQ(pts.back().position, pts.front().position);
    EXPECT_LE((pts[pts.size() - 2].position - pts.front().position).norm(), step + 1e-9)
        << "the loop is closed at its last vertex before the seed";
    // One revolution, no overlap: the inscribed polygon is short of 2πr by 2πr·θ²/24.
    EXPECT_LT(2.0 * kPi * rmax - line.length(), 2.0 * kPi * rmax * theta * theta / 12.0) << "r = " << rmax;
    EXPECT_GT(2.0 * kPi * rmax - line.length(), -1e-9) << "r = " << rmax;
  }
  EXPECT_GE(closed, 12);
}

TEST(Streamlines, UniformFlowStraightAndEvenlySpaced) {
  const auto g = square_grid();
  const Vec2 dir(std::cos(kPi / 6), std::sin(kPi / 6));
  const VectorField f(g, 0.4 * dir);
  StreamlineOptions o;
  o.separation = 0.1;
  const auto lines = trace_streamlines(f, {}, o);
  ASSERT_GE(lines.size(), 20u);
  const Vec2 n(-dir.y(), dir.x());
  std::vector<double> offsets;
  for (const auto& line : lines) {
    const double c = n.dot(line.points.front().position);
    for (const auto& p : line.points) EXPECT_NEAR(n.dot(p.position), c, 1e-12);
    EXPECT_GT(dir.dot(line.points.back().position - line.points.front().position), 0.0) << "oriented with v";
    for (const auto& p : line.points) EXPECT_NEAR(p.speed, 0.4, 1e-12);
    offsets.push_back(c);
  }
  std::sort(offsets.begin(), offsets.end());
  for (std::size_t i = 1; i < offsets.size(); ++i)
    EXPECT_NEAR(offsets[i] - offsets[i - 1], o.separation, 0.02 * o.separation) << "between lines " << i - 1
                                                                                  << " and " << i;
  // The family spans the square: its extreme lines lie within d_sep of the corners.
  const double span = std::abs(n.dot(Vec2(1.0, -1.0)));  // corner offset, either side
  EXPECT_GT(offsets.back(), span - 1.5 * o.separation);
  EXPECT_LT(offsets.front(), -span + 1.5 * o.separation);
}

// ---------------------------------------------------------------------------------------
// Seeding (Jobard & Lefer)

TEST(Streamlines, NoTwoLinesCloserThanDTestBruteForce) {
  const auto g = square_grid();
  // Cellular flow: closed cells, saddles, separatrices and stagnation points.
  const VectorField cells = sample_field(g, [](const Vec2& p) {
    return Vec2(std::sin(kPi * p.x()) * std::cos(kPi * p.y()), -std::cos(kPi * p.x()) * std::sin(kPi * p.y()));
  });
  const Cylinder cyl;
  const VectorField around = cylinder_field(cyl, g);
  const SolidCircle solid{Vec2::Zero(), cyl.a};
  for (const double tf : {0.5, 0.8}) {
    StreamlineOptions o;
    o.separation = 0.1;
    o.test_fraction = tf;
    const auto a = trace_streamlines(cells, {}, o);
    const auto b = trace_streamlines(around, {&solid, 1}, o);
    ASSERT_GE(a.size(), 10u);
    ASSERT_GE(b.size(), 10u);
    EXPECT_GE(min_interline_distance(a), tf * o.separation) << "cellular flow, d_test fraction " << tf;
    EXPECT_GE(min_interline_distance(b), tf * o.separation) << "cylinder flow, d_test fraction " << tf;
  }
}

TEST(Streamlines, CoverageLeavesNoHoleWiderThanTwoSeparations) {
  const Cylinder cyl;
  const auto g = square_grid();
  const VectorField f = cylinder_field(cyl, g);
  const SolidCircle solid{Vec2::Zero(), cyl.a};
  StreamlineOptions o;
  o.separation = 0.08;
  const auto lines = trace_streamlines(f, {&solid, 1}, o);
  const VelocitySampler s(f, {&solid, 1}, Vec2::Zero());
  grainflow::core::Rng rng(3);
  int tested = 0;
  for (int i = 0; i < 400; ++i) {
    const Vec2 p(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0));
    // Only where a disc of 2·d_sep around p is fully usable (away from blocked zones).
    if (p.norm() < cyl.a + 2.0 * o.separation + 2.0 * g.dx()) continue;
    if (std::abs(p.x()) > 1.0 - 2.0 * o.separation || std::abs(p.y()) > 1.0 - 2.0 * o.separation) continue;
    ++tested;
    double d = 1e9;
    for (const auto& l : lines)
      for (const auto& q : l.points) d = std::min(d, (q.position - p).norm());
    EXPECT_LT(d, 2.0 * o.separation) << "hole around " << p.transpose();
  }
  EXPECT_GT(tested, 100);
}

TEST(Streamlines, SelfProximityStopsASpiral) {
  // A focus: v = Ω×r - k r spirals into the centre, the gap between turns shrinking as
  // 2πk·r. Lines must not be closed, must stay d_test away from their own earlier turns
  // (beyond the 2·d_test arc window) and some must end on that test, not on stagnation.
  const auto g = square_grid();
  const VectorField f = sample_field(g, [](const Vec2& p) { return Vec2(-p.y() - 0.02 * p.x(), p.x() - 0.02 * p.y()); });
  StreamlineOptions o;
  o.separation = 0.1;
  o.min_speed_fraction = 0.2;  // stagnant for r < 0.28, where turns are < 0.035 < d_test apart
  const auto lines = trace_streamlines(f, {}, o);
  ASSERT_FALSE(lines.empty());
  const double d_test = 0.5 * o.separation;
  int self_stopped = 0;
  for (const auto& l : lines) {
    EXPECT_FALSE(l.closed);
    const auto& pts = l.points;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      for (std::size_t j = i + 1; j < pts.size(); ++j) {
        if (pts[j].arc_length - pts[i].arc_length > 2.0 * d_test + 1e-9) {
          ASSERT_GE((pts[j].position - pts[i].position).norm(), d_test);
        }
      }
    }
    const auto& end = pts.back();
    for (const auto& q : pts)
      if (end.arc_length - q.arc_length > 2.0 * d_test && (end.position - q.position).norm() < d_test + 0.02) {
        ++self_stopped;
        break;
      }
  }
  EXPECT_GE(self_stopped, 1);
}

TEST(Streamlines, DeterministicAndRespectsMaxLinesAndLength) {
  const Cylinder cyl;
  const auto g = square_grid();
  const VectorField f = cylinder_field(cyl, g);
  const SolidCircle solid{Vec2::Zero(), cyl.a};
  StreamlineOptions o;
  o.separation_fraction = 0.02;
  o.max_length = 0.5;
  o.max_lines = 40;
  const auto a = trace_streamlines(f, {&solid, 1}, o);
  const auto b = trace_streamlines(f, {&solid, 1}, o);
  ASSERT_EQ(a.size(), 40u);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].points.size(), b[i].points.size());
    for (std::size_t k = 0; k < a[i].points.size(); ++k) ASSERT_EQ(a[i].points[k].position, b[i].points[k].position);
    EXPECT_LE(a[i].length(), 0.5 + 1e-12);
  }
}

// ---------------------------------------------------------------------------------------
// Robustness and options

TEST(Streamlines, NanAndInfBinsAreAvoided) {
  const auto g = square_grid();
  VectorField f(g, Vec2(1.0, 0.2));
  grainflow::core::Rng rng(11);
  std::vector<std::size_t> bad;
  for (int k = 0; k < 150; ++k) {
    const std::size_t i = rng.below(g.size());
    f.values[i] = k % 3 == 0 ? Vec2(std::nan(""), 0.0)
                : k % 3 == 1 ? Vec2(0.0, -std::numeric_limits<double>::infinity())
                             : Vec2(std::numeric_limits<double>::infinity(), 1.0);
    bad.push_back(i);
  }
  StreamlineOptions o;
  o.separation_fraction = 0.02;
  const auto lines = trace_streamlines(f, {}, o);
  ASSERT_FALSE(lines.empty());
  for (const auto& l : lines)
    for (const auto& p : l.points) {
      ASSERT_TRUE(std::isfinite(p.position.x()) && std::isfinite(p.position.y()) && std::isfinite(p.speed));
      // No vertex within the stencil (centre distance < 1 bin per axis) of a bad bin.
      for (const std::size_t i : bad) {
        const Vec2 c = g.centre(static_cast<int>(i % g.nx), static_cast<int>(i / g.nx));
        EXPECT_FALSE(std::abs(p.position.x() - c.x()) < g.dx() - 1e-9 && std::abs(p.position.y() - c.y()) < g.dy() - 1e-9);
      }
    }
}

TEST(Streamlines, EmptyOrDegenerateFieldsGiveNoLines) {
  const auto g = square_grid();
  VectorField masked(g, Vec2(1.0, 0.0));
  std::fill(masked.mask.begin(), masked.mask.end(), 0);
  EXPECT_TRUE(trace_streamlines(masked, {}, {}).empty());
  EXPECT_TRUE(trace_streamlines(VectorField(g, Vec2::Zero()), {}, {}).empty());
  VectorField nan(g, Vec2(std::nan(""), 1.0));
  EXPECT_TRUE(trace_streamlines(nan, {}, {}).empty());
  // A 1×1 grid: one bin, constant field; no crash, a straight line.
  GridGeometry one = square_grid(1);
  const auto l1 = trace_streamlines(VectorField(one, Vec2(0.0, 1.0)), {}, {});
  ASSERT_FALSE(l1.empty());
  for (const auto& p : l1[0].points) EXPECT_NEAR(p.position.x(), 0.0, 1e-12);
  // A seed far outside the domain falls back to the lattice.
  StreamlineOptions far;
  far.seed_start = Vec2(1e300, -1e300);
  EXPECT_FALSE(trace_streamlines(VectorField(g, Vec2(1.0, 0.0)), {}, far).empty());
  // A solid circle covering the whole domain.
  const SolidCircle all{Vec2::Zero(), 5.0};
  EXPECT_TRUE(trace_streamlines(VectorField(g, Vec2(1.0, 0.0)), {&all, 1}, {}).empty());
}

TEST(Streamlines, ReferenceVelocityIsSubtracted) {
  const auto g = square_grid();
  StreamlineOptions o;
  o.reference_velocity = Vec2(0.3, -0.1);
  EXPECT_TRUE(trace_streamlines(VectorField(g, Vec2(0.3, -0.1)), {}, o).empty()) << "zero relative field";
  // Co-moving frame of the cylinder flow: v - U, reported speeds are relative ones.
  const Cylinder cyl;
  const VectorField f = cylinder_field(cyl, g);
  const SolidCircle solid{Vec2::Zero(), cyl.a};
  o.reference_velocity = Vec2(cyl.U, 0.0);
  o.separation_fraction = 0.04;
  const auto lines = trace_streamlines(f, {&solid, 1}, o);
  ASSERT_FALSE(lines.empty());
  for (const auto& l : lines)
    for (const auto& p : l.points)
      EXPECT_NEAR(p.speed, (cyl.velocity(p.position) - Vec2(cyl.U, 0.0)).norm(), 0.03 * cyl.U);
}

TEST(Streamlines, InvalidOptionsAreErrors) {
  const VectorField f(square_grid(), Vec2(1.0, 0.0));
  const auto bad = [&](auto set) {
    StreamlineOptions o;
    set(o);
    EXPECT_THROW(trace_streamlines(f, {}, o), grainflow::Error);
  };
  bad([](StreamlineOptions& o) { o.separation = -1.0; });
  bad([](StreamlineOptions& o) { o.separation_fraction = 0.0; });
  bad([](StreamlineOptions& o) { o.separation = 1e-9; });
  bad([](StreamlineOptions& o) { o.test_fraction = 1.5; });
  bad([](StreamlineOptions& o) { o.step_bins = 0.0; });
  bad([](StreamlineOptions& o) { o.min_speed_fraction = 1.0; });
  bad([](StreamlineOptions& o) { o.max_lines = -1; });
  bad([](StreamlineOptions& o) { o.max_length = std::nan(""); });
  try {
    StreamlineOptions o;
    o.test_fraction = 2.0;
    trace_streamlines(f, {}, o);
  } catch (const grainflow::Error& e) {
    EXPECT_NE(std::string(e.what()).find("test_fraction"), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------------------------------
// Noisy fields (regression: the time-averaged velocity of an equilibrium gas, mean ≈ 0 with
// independent bin-to-bin noise, hung in Tracer::trace_dir). RK4 on the unit direction
// field met folds where the direction turns back within one step (k1 + 2k2 + 2k3 + k4 ≈ 0):
// each step advanced ~1e-7, the arc hardly grew, no stop condition fired, and one line
// collected ~10^5 vertices in one grid cell (quadratic proximity scans): 16 s on 30×30,
// minutes on 60×60.

namespace {

// n×n bins over a 100×100 box, each bin's vector ~ N(0, sd²) per component; `masked`
// random bins get mask 0 and `nan_bins` random bins hold NaN (or inf) values.
VectorField noisy_field(int n, double sd, std::uint64_t seed, int masked = 0, int nan_bins = 0) {
  GridGeometry g;
  g.nx = g.ny = n;
  g.lo = Vec2(0.0, 0.0);
  g.hi = Vec2(100.0, 100.0);
  VectorField f(g, Vec2::Zero());
  grainflow::core::Rng rng(seed);
  for (auto& v : f.values) v = Vec2(rng.normal(0.0, sd), rng.normal(0.0, sd));
  for (int k = 0; k < masked; ++k) f.mask[rng.below(g.size())] = 0;
  for (int k = 0; k < nan_bins; ++k)
    f.values[rng.below(g.size())] = k % 2 == 0 ? Vec2(std::nan(""), 0.0)
                                               : Vec2(0.0, std::numeric_limits<double>::infinity());
  return f;
}

// Traces, checks the spacing guarantee and that no line is degenerate; returns the wall
// time in ms (the best of two calls: the machine is shared).
double trace_noisy(const VectorField& f, const StreamlineOptions& o, const char* what) {
  std::vector<Streamline> lines;
  double best = 1e30;
  for (int rep = 0; rep < 2; ++rep) {
    const auto t0 = std::chrono::steady_clock::now();
    lines = trace_streamlines(f, {}, o);
    best = std::min(best, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  const double d_sep = o.separation > 0.0 ? o.separation : o.separation_fraction * 100.0;
  EXPECT_GE(lines.size(), 50u) << what;
  EXPECT_GE(min_interline_distance(lines), o.test_fraction * d_sep) << what;
  std::size_t pts = 0, longest = 0;
  for (const auto& l : lines) {
    pts += l.points.size();
    longest = std::max(longest, l.points.size());
    for (std::size_t i = 1; i < l.points.size(); ++i)
      EXPECT_GT(l.points[i].arc_length, l.points[i - 1].arc_length) << what << ": repeated vertex";
  }
  std::printf("%-44s %4zu lines %6zu vertices (longest %4zu) %7.2f ms\n", what, lines.size(), pts, longest, best);
  return best;
}

}  // namespace

TEST(Streamlines, NoisyZeroMeanFieldFinishesQuickly) {
  // Measured after the fix: 3–6 ms per call (30×30 and 60×60); before it, 16 s on 30×30.
  // The bound leaves a wide margin for a loaded machine or a debug build.
  StreamlineStyle style;                 // what StreamlineLayer passes by default
  StreamlineOptions layer = style.trace;
  layer.reference_velocity = Vec2(0.0, 0.0);
  // Without a reference velocity the noise amplitude only scales the field (directions and
  // the relative stagnation cutoff are unchanged), so seeds vary rather than sd here.
  for (const int n : {30, 60})
    for (const std::uint64_t seed : {1u, 2u, 3u}) {
      const VectorField f = noisy_field(n, 0.05, seed);
      char what[96];
      std::snprintf(what, sizeof what, "noise %dx%d seed %llu", n, n, static_cast<unsigned long long>(seed));
      EXPECT_LT(trace_noisy(f, StreamlineOptions{}, what), n == 60 ? 200.0 : 100.0) << what;
      std::snprintf(what, sizeof what, "noise %dx%d seed %llu (layer options)", n, n,
                    static_cast<unsigned long long>(seed));
      EXPECT_LT(trace_noisy(f, layer, what), n == 60 ? 200.0 : 100.0) << what;
    }
}

TEST(Streamlines, NoisyFieldWithMaskedAndNanBinsFinishesQuickly) {
  StreamlineStyle style;
  StreamlineOptions layer = style.trace;
  layer.reference_velocity = Vec2(0.01, -0.005);  // relative_to_reference with a small U
  for (const int n : {30, 60})
    for (const double sd : {0.02, 0.1}) {
      const VectorField f = noisy_field(n, sd, 5, n / 3, n / 4);
      char what[96];
      std::snprintf(what, sizeof what, "noise %dx%d sd %.2f, masked + NaN bins", n, n, sd);
      EXPECT_LT(trace_noisy(f, StreamlineOptions{}, what), n == 60 ? 200.0 : 100.0) << what;
      std::snprintf(what, sizeof what, "noise %dx%d sd %.2f, masked + NaN (layer, U)", n, n, sd);
      EXPECT_LT(trace_noisy(f, layer, what), n == 60 ? 200.0 : 100.0) << what;
    }
}

TEST(Streamlines, NoisyFieldWorkIsBoundedWithoutStagnationCutoff) {
  // No stagnation threshold, denser lines and a finer step: the only stops left are the
  // geometric ones and the per-line work bound.
  StreamlineOptions o;
  o.min_speed_fraction = 0.0;
  o.separation_fraction = 0.02;
  o.step_bins = 0.1;
  for (const int n : {30, 60}) {
    const VectorField f = noisy_field(n, 0.05, 9, 4, 4);
    char what[96];
    std::snprintf(what, sizeof what, "noise %dx%d, min_speed 0, d_sep 2%%, step 0.1", n, n);
    EXPECT_LT(trace_noisy(f, o, what), 500.0) << what;
  }
}

// ---------------------------------------------------------------------------------------
// Arrowheads and quiver

TEST(Arrowheads, EverySpacingAlongTheArc) {
  Streamline l;
  for (int i = 0; i <= 100; ++i) l.points.push_back({Vec2(0.01 * i, 0.5), 1.0 + 0.01 * i, 0.01 * i});
  Streamline short_line;
  short_line.points = {{Vec2(0, 0), 1.0, 0.0}, {Vec2(0, 0.1), 3.0, 0.1}};
  const std::vector<Streamline> lines{l, short_line};
  const auto arrows = place_arrowheads(lines, 0.3);
  // Long line (length 1): 3 arrows centred, at 0.2, 0.5, 0.8; short line (0.1 < 0.3):
  // one at its middle.
  ASSERT_EQ(arrows.size(), 4u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(arrows[k].position.x(), 0.2 + 0.3 * k, 1e-12);
    EXPECT_NEAR(arrows[k].position.y(), 0.5, 1e-12);
    EXPECT_NEAR(arrows[k].direction.x(), 1.0, 1e-12);
    EXPECT_NEAR(arrows[k].speed, 1.2 + 0.3 * k, 1e-9);
  }
  EXPECT_NEAR(arrows[3].position.y(), 0.05, 1e-12);
  EXPECT_NEAR(arrows[3].direction.y(), 1.0, 1e-12);
  EXPECT_NEAR(arrows[3].speed, 2.0, 1e-12);
  EXPECT_THROW(place_arrowheads(lines, 0.0), grainflow::Error);
}

TEST(Quiver, RegularSubgridSkipsSolidAndMaskedBins) {
  const Cylinder cyl;
  const auto g = square_grid();
  const VectorField f = cylinder_field(cyl, g);
  const SolidCircle solid{Vec2::Zero(), cyl.a};
  const auto arrows = quiver(f, {&solid, 1}, Vec2(1.0, 0.0), 4);
  // Bins 2, 6, …, 58 on each axis: 15 × 15 minus those whose centre is inside r < a.
  int expected = 0;
  for (int iy = 2; iy < 60; iy += 4)
    for (int ix = 2; ix < 60; ix += 4) expected += g.centre(ix, iy).norm() >= cyl.a;
  ASSERT_EQ(static_cast<int>(arrows.size()), expected);
  EXPECT_LT(expected, 225);
  for (const auto& a : arrows) {
    EXPECT_NEAR((a.velocity - (cyl.velocity(a.position) - Vec2(1.0, 0.0))).norm(), 0.0, 1e-12);
    EXPECT_NEAR(a.speed, a.velocity.norm(), 1e-15);
  }
  EXPECT_THROW(quiver(f, {}, Vec2::Zero(), 0), grainflow::Error);
}
