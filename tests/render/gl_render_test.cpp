// Golden-image tests of the particle layers on both off-screen backends.
//
// Comparator thresholds (render/image/compare.hpp): a pixel counts as different when its
// largest channel differs by more than kMaxChannel = 12 levels; at most kMaxFraction =
// 0.05 % of the pixels (32 of a 320×200 frame) may differ. Why so loose rather than exact: the goldens are made
// with Mesa 22.3.6 llvmpipe; other Mesa/LLVM versions round anti-aliased edges and the
// sphere lighting slightly differently, which moves edge pixels by a few levels. A moved
// particle changes hundreds of pixels by far more (the "must fail" test below proves it).
//
// GRAINFLOW_UPDATE_GOLDEN=1 rewrites the golden images (commit them with the reason).
// On failure the actual image and a diff heat map are written to GRAINFLOW_TEST_OUT.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "engine/core/error.hpp"
#include "engine/core/rng.hpp"
#include "render/context/gl_context.hpp"
#include "render/frame_renderer.hpp"
#include "render/image/compare.hpp"
#include "render/output/png_io.hpp"
#include "tests/render/golden_support.hpp"

namespace fs = std::filesystem;
using namespace grainflow;
using namespace grainflow::render;

namespace {

constexpr int kMaxChannel = 12;
constexpr double kMaxFraction = 0.0005;

// A 2D box of polydisperse disks on a jittered triangular lattice with a central obstacle,
// coloured by a smooth function of position; deterministic through core::Rng.
Snapshot disk_scene() {
  Snapshot s;
  s.dim = 2;
  s.lo = {0, 0, 0};
  s.hi = {24, 14, 0};
  core::Rng rng(7);
  for (int j = 0; j < 14; ++j)
    for (int i = 0; i < 24; ++i) {
      const double x = 0.5 + i + 0.5 * (j % 2) + 0.1 * rng.uniform(-1, 1);
      const double y = 0.5 + j * 0.96 + 0.1 * rng.uniform(-1, 1);
      if (std::hypot(x - 12, y - 7) < 3.2 || x > 23.6) continue;
      const double r = 0.38 + 0.1 * rng.uniform();
      s.pos_radius.insert(s.pos_radius.end(), {float(x), float(y), 0.f, float(r)});
      s.attribute.push_back(float(std::sin(x / 4) + y / 14));
    }
  s.attribute_name = "test";
  s.obstacles.push_back({{12, 7}, 2.5});
  return s;
}

// A 5×4×3 block of spheres in a box, coloured by height, one of them NaN (grey).
Snapshot sphere_scene() {
  Snapshot s;
  s.dim = 3;
  s.lo = {0, 0, 0};
  s.hi = {6, 5, 4};
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 5; ++i) {
        s.pos_radius.insert(s.pos_radius.end(), {0.9f + i * 1.05f, 0.9f + j * 1.05f, 0.6f + k * 1.05f, 0.5f});
        s.attribute.push_back(float(k + 0.2 * i));
      }
  s.attribute[7] = std::nanf("");
  return s;
}

// One disk of radius r at (x, y) in the square 2D box [0, side]².
Snapshot one_disk(double side, float x, float y, float r) {
  Snapshot s;
  s.lo = {0, 0, 0};
  s.hi = {side, side, 0};
  s.pos_radius = {x, y, 0.f, r};
  return s;
}

bool lit(const Image& img, int x, int y) { return img.pixel(x, y)[0] + img.pixel(x, y)[1] + img.pixel(x, y)[2] > 0; }

// No domain outline, black background: a pixel is lit only where a particle is drawn.
FrameStyle plain_style() {
  FrameStyle style;
  style.draw_domain = false;
  style.background = {0, 0, 0};
  return style;
}

class GlRender : public ::testing::TestWithParam<Backend> {
protected:
  void SetUp() override {
    ctx_ = golden::context_or_null(GetParam());
    if (!ctx_) GTEST_SKIP() << "no " << backend_name(GetParam()) << " context on this machine";
  }
  std::unique_ptr<GlContext> ctx_;
};

TEST_P(GlRender, DisksMatchGolden) {
  FrameRenderer r(*ctx_, 320, 200);
  FrameStyle style;
  golden::check_golden(r.render(disk_scene(), style), "disks_2d", {kMaxChannel, kMaxFraction});
}

TEST_P(GlRender, SpheresMatchGolden) {
  FrameRenderer r(*ctx_, 320, 240, 4);
  FrameStyle style;
  style.colormap = Colormap(ColormapId::inferno);
  style.range = std::pair{0.0, 3.0};
  golden::check_golden(r.render(sphere_scene(), style), "spheres_3d", {kMaxChannel, kMaxFraction});
}

// The comparator must notice a single moved particle at the thresholds used above.
TEST_P(GlRender, MovedParticleFailsComparison) {
  FrameRenderer r(*ctx_, 320, 200);
  Snapshot s = disk_scene();
  const Image before = r.render(s, {});
  s.pos_radius[4 * 40] += 0.6f;  // one disk moved by 0.6 of a diameter
  const Image after = r.render(s, {});
  const auto res = compare_images(before, after, {kMaxChannel, kMaxFraction});
  EXPECT_FALSE(res.passed);
  EXPECT_GT(res.max_channel_diff, 60);
}

// Same scene twice, and across backends: identical pixels (deterministic rendering).
TEST_P(GlRender, DeterministicAcrossFrames) {
  FrameRenderer r(*ctx_, 160, 100);
  const Image a = r.render(disk_scene(), {});
  const Image b = r.render(disk_scene(), {});
  EXPECT_EQ(a.rgba, b.rgba);
}

TEST_P(GlRender, ReadbackRowOrderIsTopFirst) {
  // One big disk in the upper half of the domain must appear in the upper rows.
  FrameRenderer r(*ctx_, 100, 100);
  const Image& img = r.render(one_disk(10, 5.f, 8.f, 1.5f), plain_style());
  EXPECT_TRUE(lit(img, 50, 21));   // world y = 8 → image row ≈ 100·(1 − 0.8) (+ margin)
  EXPECT_FALSE(lit(img, 50, 79));  // world y = 2 is empty
}

TEST_P(GlRender, LargeParticlesUseQuadsAndStayRound) {
  // A disk wider than the driver's largest point sprite: drawn by the quad path, the
  // filled area matches π r² within 2 %.
  FrameRenderer r(*ctx_, 800, 800);
  const Image& img = r.render(one_disk(1, 0.5f, 0.5f, 0.4f), plain_style());
  double covered = 0;
  for (int y = 0; y < 800; ++y)
    for (int x = 0; x < 800; ++x) covered += img.pixel(x, y)[3] > 0 && img.pixel(x, y)[1] > 0 ? 1 : 0;
  const double ppu = 800 * (1 - 2 * 0.03);
  const double expected = M_PI * std::pow(0.4 * ppu, 2);
  EXPECT_NEAR(covered / expected, 1.0, 0.02);
}

TEST_P(GlRender, PeriodicDisksShowTheirImageAndAreClippedToTheBox) {
  // A disk across the right edge of a box periodic in x: its image shows at the left edge
  // and nothing is drawn right of the box; without the flag, the reverse.
  Snapshot s = one_disk(10, 9.5f, 5.f, 1.5f);
  FrameRenderer r(*ctx_, 200, 100);
  // The box fills 94 % of the height, centred: 9.4 px per unit, x from 53 px.
  const auto column = [](double x) { return int(std::lround(53 + 9.4 * x)); };
  for (bool periodic : {true, false}) {
    s.periodic = {periodic, false, false};
    const Image& img = r.render(s, plain_style());
    EXPECT_TRUE(lit(img, column(9.0), 50)) << "periodic = " << periodic;           // the disk itself
    EXPECT_EQ(lit(img, column(0.4), 50), periodic) << "periodic = " << periodic;   // its image
    EXPECT_EQ(lit(img, column(10.5), 50), !periodic) << "periodic = " << periodic; // beyond the box
  }
}

TEST_P(GlRender, PeriodicSpheresShowTheirImageAndAreCutAtTheBox) {
  // A sphere across the +x face of a box periodic in x, seen orthographically along +y (x
  // to the right, z up): its image shows inside the −x face and nothing is drawn beyond
  // the +x face; without the flag, the reverse. Also at an edge (periodic in x and z) the
  // diagonal image shows in the opposite corner.
  Snapshot s;
  s.dim = 3;
  s.lo = {0, 0, 0};
  s.hi = {10, 10, 10};
  s.pos_radius = {9.5f, 5.f, 5.f, 1.5f};
  FrameStyle style = plain_style();
  style.camera.azimuth_deg = -90.0;
  style.camera.elevation_deg = 0.0;
  style.camera.orthographic = true;
  const int w = 200, h = 200;
  FrameRenderer r(*ctx_, w, h);
  const ViewTransform view = fit_3d(s.lo, s.hi, style.camera, w, h);
  const auto lit_at = [&](const Image& img, double x, double z) {
    const Eigen::Vector4f c = view.view_proj() * Eigen::Vector4f(float(x), 5.f, float(z), 1.f);
    return lit(img, int(std::lround((c.x() + 1) * 0.5 * w)), int(std::lround((1 - c.y()) * 0.5 * h)));
  };
  for (bool periodic : {true, false}) {
    s.periodic = {periodic, false, false};
    const Image& img = r.render(s, style);
    EXPECT_TRUE(lit_at(img, 9.0, 5.0)) << "periodic = " << periodic;              // the sphere itself
    EXPECT_EQ(lit_at(img, 0.4, 5.0), periodic) << "periodic = " << periodic;      // its image
    EXPECT_EQ(lit_at(img, 10.6, 5.0), !periodic) << "periodic = " << periodic;    // beyond the box
  }
  s.pos_radius = {9.5f, 5.f, 9.5f, 1.5f};
  s.periodic = {true, false, true};
  const Image& img = r.render(s, style);
  EXPECT_TRUE(lit_at(img, 0.4, 0.4));    // the diagonal image
  EXPECT_TRUE(lit_at(img, 0.4, 9.5));    // the x image
  EXPECT_TRUE(lit_at(img, 9.5, 0.4));    // the z image
  EXPECT_FALSE(lit_at(img, 10.6, 9.5));  // beyond the box in x
  EXPECT_FALSE(lit_at(img, 9.5, 10.6));  // and in z
}

// A dense block of spheres: culling hidden spheres on the CPU draws far fewer of them and
// leaves the picture unchanged, in perspective and in orthographic views.
TEST_P(GlRender, SphereCullingKeepsThePicture) {
  Snapshot s;
  s.dim = 3;
  s.lo = {0, 0, 0};
  s.hi = {20.4, 20.4, 20.4};
  for (int k = 0; k < 20; ++k)
    for (int j = 0; j < 20; ++j)
      for (int i = 0; i < 20; ++i) {
        s.pos_radius.insert(s.pos_radius.end(), {0.51f + i * 1.02f, 0.51f + j * 1.02f, 0.51f + k * 1.02f, 0.5f});
        s.attribute.push_back(float(i + j + k));
      }
  for (bool ortho : {false, true}) {
    FrameRenderer r(*ctx_, 400, 300);
    FrameStyle style;
    style.camera.orthographic = ortho;
    r.particle_layer().sphere_culling = SphereCulling::Off;
    const Image all = r.render(s, style);
    EXPECT_EQ(r.particle_layer().last_spheres_drawn(), 8000u);
    r.particle_layer().sphere_culling = SphereCulling::On;
    const Image culled = r.render(s, style);
    EXPECT_LT(r.particle_layer().last_spheres_drawn(), 4000u) << "ortho " << ortho;  // measured 3575 and 3046
    const auto res = compare_images(all, culled, {0, 0.0});
    EXPECT_TRUE(res.passed) << "ortho " << ortho << ": " << res.pixels_over << " pixels differ, max "
                            << res.max_channel_diff;
  }
}

TEST_P(GlRender, RejectsAbsurdSizes) {
  EXPECT_THROW(FrameRenderer(*ctx_, 0, 100), Error);
  EXPECT_THROW(FrameRenderer(*ctx_, 100000, 100), Error);
}

INSTANTIATE_TEST_SUITE_P(Backends, GlRender, ::testing::Values(Backend::Egl, Backend::OSMesa),
                         [](const auto& info) { return std::string(backend_name(info.param)); });

TEST(GlBackends, ParseBackendNames) {
  EXPECT_EQ(parse_backend("auto"), Backend::Auto);
  EXPECT_EQ(parse_backend("egl"), Backend::Egl);
  EXPECT_EQ(parse_backend("osmesa"), Backend::OSMesa);
  try {
    parse_backend("vulkan");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("vulkan"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("auto, egl, osmesa"), std::string::npos);
  }
}

}  // namespace
