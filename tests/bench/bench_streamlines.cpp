// Throughput of the streamline tracer (render/layers/streamlines.*) on a 60×60 binned
// field: potential flow past a cylinder plus a swirl behind it (an eddy pair), the kind
// of picture of seed 003 Fig. 4.2–4.22. Prints lines, vertices and milliseconds per call.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>

#include "render/layers/streamlines.hpp"
#include "tests/bench/bench_args.hpp"

using grainflow::Vec2;
using namespace grainflow::render;

namespace {

// Thread CPU time: the machine is shared, wall time includes time spent descheduled.
double thread_cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

grainflow::core::VectorField make_field() {
  grainflow::core::GridGeometry g;
  g.nx = g.ny = 60;
  g.lo = Vec2(-1.0, -1.0);
  g.hi = Vec2(1.0, 1.0);
  grainflow::core::VectorField f(g, Vec2::Zero());
  const double a = 0.25;
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) {
      const Vec2 p = g.centre(ix, iy);
      const double r2 = p.squaredNorm(), r4 = r2 * r2;
      Vec2 v(1.0 - a * a * (p.x() * p.x() - p.y() * p.y()) / r4, -2.0 * a * a * p.x() * p.y() / r4);
      for (const double sy : {-1.0, 1.0}) {  // counter-rotating eddies behind the obstacle
        const Vec2 d = p - Vec2(0.45, 0.2 * sy);
        v += -sy * 0.8 * std::exp(-d.squaredNorm() / 0.02) * Vec2(-d.y(), d.x()) / 0.15;
      }
      f.at(ix, iy) = v;
      if (p.norm() < a) f.mask[g.index(ix, iy)] = 0;
    }
  return f;
}

void run(const char* name, const grainflow::core::VectorField& f, const SolidCircle& solid,
         const StreamlineOptions& o) {
  std::vector<Streamline> lines;
  double best_wall = 1e30, best_cpu = 1e30;
  for (int rep = 0; rep < 20; ++rep) {
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = thread_cpu_ms();
    lines = trace_streamlines(f, {&solid, 1}, o);
    best_cpu = std::min(best_cpu, thread_cpu_ms() - c0);
    best_wall = std::min(best_wall, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  std::size_t pts = 0;
  for (const auto& l : lines) pts += l.points.size();
  std::printf("%-40s %5zu lines %7zu vertices  cpu %6.2f ms  wall %6.2f ms  %5.1f Mvertex/s (cpu)\n", name,
              lines.size(), pts, best_cpu, best_wall, pts / best_cpu / 1e3);
}

}  // namespace

int main(int argc, char** argv) {
  grainflow::bench::at_most("bench_streamlines", "bench_streamlines (no arguments)", argc, argv, 0);
  const auto f = make_field();
  const SolidCircle solid{Vec2::Zero(), 0.25};
  StreamlineOptions o;
  o.separation_fraction = 0.03;
  run("d_sep 3% of width (picture density)", f, solid, o);
  o.separation_fraction = 0.01;
  run("d_sep 1% of width", f, solid, o);
  o.max_length = 0.2;
  run("d_sep 1%, max_length 10% of width", f, solid, o);
  o.separation_fraction = 0.02;
  o.max_length = 0.1;
  run("d_sep 2%, max_length 5% of width", f, solid, o);
  return 0;
}
