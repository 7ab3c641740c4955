// Throughput of a multi-panel field frame (issue 3): 1920×1080, 2×2 panels — 1.6×10^5
// disks | 60×60 density map | 60×60 kT map | ~1,000 streamlines over |v| — with titles,
// colour bars and caption, render + read-back, on EGL (or the backend given as argv[1]).
// Prints wall and process-CPU milliseconds per frame (the machine is shared).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>

#include "engine/core/error.hpp"
#include "engine/core/rng.hpp"
#include "render/context/gl_context.hpp"
#include "render/frame_renderer.hpp"
#include "render/panel_renderer.hpp"
#include "tests/bench/bench_args.hpp"

using namespace grainflow;
using namespace grainflow::render;

namespace {

double process_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

// Seed 003 §4.2 reference geometry: 440 × 440, η ≈ 0.65, obstacle D = 74 at 110 upstream.
Snapshot make_scene() {
  Snapshot s;
  s.dim = 2;
  s.lo = {0, 0, 0};
  s.hi = {440, 440, 0};
  const Vec2 c(110, 220);
  const double a = 37;
  s.obstacles.push_back({c, a});
  core::Rng rng(1);
  const double spacing = 1.0 / std::sqrt(0.83 * 0.866);  // triangular lattice, n = 0.83
  for (double y = 0.5; y < 440; y += spacing * 0.866)
    for (double x = 0.5; x < 440; x += spacing) {
      if ((Vec2(x, y) - c).norm() < a + 0.5) continue;
      s.pos_radius.insert(s.pos_radius.end(), {float(x + 0.05 * rng.uniform(-1, 1)), float(y), 0.f, 0.5f});
      s.attribute.push_back(float(rng.uniform()));
    }
  core::GridGeometry g;
  g.nx = g.ny = 60;
  g.lo = Vec2(0, 0);
  g.hi = Vec2(440, 440);
  core::ScalarField density(g), kt(g);
  core::VectorField v(g);
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) {
      const Vec2 p = g.centre(ix, iy) - c;
      const double r2 = p.squaredNorm(), r4 = r2 * r2;
      Vec2 u(1.0 - a * a * (p.x() * p.x() - p.y() * p.y()) / r4, -2.0 * a * a * p.x() * p.y() / r4);
      for (const double sy : {-1.0, 1.0}) {  // an eddy pair behind the obstacle
        const Vec2 d = p - Vec2(70, 30 * sy);
        u += -sy * 0.8 * std::exp(-d.squaredNorm() / 900) * Vec2(-d.y(), d.x()) / 30;
      }
      const auto k = g.index(ix, iy);
      v.values[k] = 0.1 * u;
      density.values[k] = 0.83 + 0.05 * std::sin(p.x() / 40);
      kt.values[k] = 0.02 + 0.01 * std::exp(-r2 / 4000);
      if (std::sqrt(r2) < a) density.mask[k] = kt.mask[k] = v.mask[k] = 0;
    }
  s.fields.push_back({"density", "n", density});
  s.fields.push_back({"temperature", "kT", kt});
  s.velocity = v;
  s.reference_velocity = Eigen::Vector2d(0.1, 0);
  s.labels = {{"t", "1200"}, {"U", "0.1"}, {"τ_E", "480"}, {"N", std::to_string(s.size())}};
  return s;
}

}  // namespace

int main(int argc, char** argv) try {
  constexpr const char* kUsage = "bench_fields [egl|osmesa|auto] [frames=20] [separation=5] [max-length=60]";
  bench::at_most("bench_fields", kUsage, argc, argv, 4);
  Backend backend{};
  try {
    backend = parse_backend(argc > 1 ? argv[1] : "egl");
  } catch (const Error& e) {
    bench::usage_error("bench_fields", kUsage, e.what());
  }
  const int frames = argc > 2 ? static_cast<int>(bench::number_arg("bench_fields", kUsage, "frames", argv[2], 1, 1e5, true)) : 20;
  // Short lines at a readable spacing (≈ 5 px on the 1080p panel) give ~1,000 streamlines.
  const double separation = argc > 3 ? bench::number_arg("bench_fields", kUsage, "separation", argv[3], 0.5, 1e3) : 5.0;
  const double max_length = argc > 4 ? bench::number_arg("bench_fields", kUsage, "max-length", argv[4], 1, 1e4) : 60.0;
  auto ctx = create_context(backend);
  const Snapshot s = make_scene();
  const std::vector<std::string> names = {"particles", "density", "temperature", "streamlines"};
  FrameLayout layout = make_layout(2, 2, names);
  layout.panels[3].streamlines.trace.separation = separation;
  layout.panels[3].streamlines.trace.max_length = max_length;
  layout.panels[3].streamlines.arrow_spacing = max_length;
  FrameStyle style;
  style.range = std::pair{0.0, 1.0};
  FrameRenderer r(*ctx, 1920, 1080);
  r.render(s, style, layout);  // warm-up: shaders, glyph atlas
  double best_wall = 1e30, sum_wall = 0, sum_cpu = 0;
  for (int i = 0; i < frames; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = process_cpu_ms();
    r.render(s, style, layout);
    const double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    sum_cpu += process_cpu_ms() - c0;
    sum_wall += wall;
    best_wall = std::min(best_wall, wall);
  }
  // Streamline count of the last frame, traced once more outside the timing.
  StreamlineLayer probe(ctx->gl());
  std::vector<Segment> segs;
  std::vector<SolidCircle> solids = {{s.obstacles[0].centre, s.obstacles[0].radius}};
  const auto t0 = std::chrono::steady_clock::now();
  probe.build(*s.velocity, solids, layout.panels[3].streamlines, Vec2(0, 0), 1.07f, segs);
  const double build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::printf("backend %s (%s): 1920x1080 2x2, %zu disks, 60x60 fields, %zu streamlines (d_sep %.1f, max length "
              "%.0f; %zu segments incl. arrowheads; trace+build %.1f ms)\n",
              ctx->backend().c_str(), ctx->gl_renderer().c_str(), s.size(), probe.last_line_count(), separation,
              max_length, segs.size(), build_ms);
  std::printf("%d frames: mean wall %.1f ms (%.2f frames/s), best wall %.1f ms (%.2f frames/s), "
              "mean process CPU %.1f ms/frame\n",
              frames, sum_wall / frames, 1e3 * frames / sum_wall, best_wall, 1e3 / best_wall, sum_cpu / frames);
  return 0;
} catch (const grainflow::Error& e) {
  std::fprintf(stderr, "bench_fields: %s\n", e.what());
  return 1;
}
