// Render + read-back throughput of the particle layers at 1920×1080 on each backend:
// 1.6×10^5 disks (the seed-003 reference box: 440×440 at area fraction 0.65) and 10^5
// spheres. Not a test: run on purpose, prints frames/s (median of the timed frames).
//   ./tests/bench/bench_render [frames=15]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/core/rng.hpp"
#include "render/context/gl_context.hpp"
#include "render/frame_renderer.hpp"
#include "tests/bench/bench_args.hpp"

using namespace grainflow;
using namespace grainflow::render;

namespace {

Snapshot disks(int n_target) {
  // Triangular lattice of unit disks filling a square at area fraction ≈ 0.65, jittered.
  Snapshot s;
  s.dim = 2;
  const double eta = 0.65, a = std::sqrt(M_PI * 0.25 / eta * 2 / std::sqrt(3.0));
  const int nx = int(std::sqrt(n_target * std::sqrt(3.0) / 2)), ny = n_target / nx;
  s.lo = {0, 0, 0};
  s.hi = {nx * a, ny * a * std::sqrt(3.0) / 2, 0};
  core::Rng rng(1);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double x = (i + 0.5 * (j % 2)) * a + 0.05 * rng.uniform(-1, 1);
      const double y = j * a * std::sqrt(3.0) / 2 + 0.05 * rng.uniform(-1, 1);
      s.pos_radius.insert(s.pos_radius.end(), {float(x), float(y), 0.f, 0.5f});
      s.attribute.push_back(float(rng.normal()));
    }
  s.obstacles.push_back({{0.25 * s.hi.x(), 0.5 * s.hi.y()}, 37});
  return s;
}

Snapshot spheres(int n_target) {
  Snapshot s;
  s.dim = 3;
  const int side = int(std::cbrt(n_target));
  s.lo = {0, 0, 0};
  s.hi = {side * 1.02, side * 1.02, side * 1.02};
  core::Rng rng(2);
  for (int k = 0; k < side; ++k)
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i) {
        s.pos_radius.insert(s.pos_radius.end(), {float((i + 0.5) * 1.02), float((j + 0.5) * 1.02),
                                                 float((k + 0.5) * 1.02), 0.5f});
        s.attribute.push_back(float(k + rng.uniform()));
      }
  return s;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

// Wall time is what a user sees on an idle machine; process CPU time (all threads,
// llvmpipe's included) is also printed because it is far less disturbed by other load.
void time_frames(GlContext& ctx, const char* what, const Snapshot& s, int msaa, int frames) {
  FrameRenderer r(ctx, 1920, 1080, msaa);
  FrameStyle style;
  r.render(s, style);  // warm-up: shader compilation, buffer allocation
  std::vector<double> wall, cpu;
  for (int i = 0; i < frames; ++i) {
    const auto a = std::chrono::steady_clock::now();
    const double c = cpu_seconds();
    r.render(s, style);
    cpu.push_back(cpu_seconds() - c);
    wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count());
  }
  const double m = median(wall), mc = median(cpu);
  std::printf("%-16s %-12s msaa %d : %7.1f ms/frame wall (%6.2f frames/s), %7.1f ms CPU", ctx.backend().c_str(),
              what, msaa, m * 1e3, 1 / m, mc * 1e3);
  if (s.dim == 3) std::printf(", %zu of %zu spheres drawn after culling", r.particle_layer().last_spheres_drawn(), s.size());
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  constexpr const char* kUsage = "bench_render [frames=15]";
  grainflow::bench::at_most("bench_render", kUsage, argc, argv, 1);
  const int frames = argc > 1 ? static_cast<int>(grainflow::bench::number_arg("bench_render", kUsage, "frames", argv[1], 1, 1e5, true)) : 15;
  const Snapshot d = disks(160000), sp = spheres(100000);
  std::printf("1920x1080 render + read-back, median of %d frames (%zu disks, %zu spheres)\n", frames, d.size(),
              sp.size());
  for (Backend b : {Backend::Egl, Backend::OSMesa}) {
    try {
      auto ctx = create_context(b);
      time_frames(*ctx, "disks 2D", d, 0, frames);
      time_frames(*ctx, "disks 2D x4", d, 4, frames);
      time_frames(*ctx, "spheres 3D", sp, 0, frames);
      time_frames(*ctx, "spheres 3D", sp, 4, frames);
    } catch (const Error& e) {
      std::printf("%s: unavailable (%s)\n", std::string(backend_name(b)).c_str(), e.what());
    }
  }
}
