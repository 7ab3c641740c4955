#include "engine/ed/initial_state.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "engine/core/error.hpp"

namespace grainflow::ed {

std::vector<DiskInit> triangular_lattice(int n, double diameter, double lx, double ly,
                                         bool periodic_x, bool periodic_y, core::Rng& rng) {
  if (n <= 0) return {};
  const double r = 0.5 * diameter;
  const double x0 = periodic_x ? 0.0 : r, wx = periodic_x ? lx : lx - diameter;
  const double y0 = periodic_y ? 0.0 : r, wy = periodic_y ? ly : ly - diameter;
  // Pick the rows × columns layout with the largest nearest-neighbour distance.
  int best_rows = 0, best_cols = 0;
  double best_d = -1.0;
  const int max_rows = std::max(1, std::min(n, static_cast<int>(wy / (0.25 * diameter)) + 1));
  for (int rows = 1; rows <= max_rows; ++rows) {
    const int cols = (n + rows - 1) / rows;
    const double ax = wx / cols, ay = wy / rows;
    double d = ax;
    if (rows > 1 || periodic_y) d = std::min(d, std::sqrt(0.25 * ax * ax + ay * ay));
    if (rows > 2 || periodic_y) d = std::min(d, 2.0 * ay);  // same stagger two rows apart
    if (periodic_y && rows % 2 == 1) d = std::min(d, ay);  // rows 0 and rows−1 are not staggered
    if (d > best_d) { best_d = d; best_rows = rows; best_cols = cols; }
  }
  if (best_d < diameter * (1.0 + 1e-9) || wx <= 0.0 || wy <= 0.0)
    throw Error(fmt::format("ed: {} disks of diameter {} do not fit without overlap on a lattice in a "
                            "{} x {} box (best spacing {:.4f}); lower N or the area fraction",
                            n, diameter, lx, ly, best_d));
  const int rows = best_rows, cols = best_cols;
  const double ax = wx / cols, ay = wy / rows;
  const std::int64_t sites = static_cast<std::int64_t>(rows) * cols;
  // Choose n of the sites uniformly (partial Fisher–Yates), then restore row order.
  std::vector<std::int64_t> idx(sites);
  for (std::int64_t k = 0; k < sites; ++k) idx[k] = k;
  if (sites > n) {
    for (int k = 0; k < n; ++k) {
      const std::int64_t pick = k + static_cast<std::int64_t>(rng.below(sites - k));
      std::swap(idx[k], idx[pick]);
    }
    idx.resize(n);
    std::sort(idx.begin(), idx.end());
  }
  std::vector<DiskInit> out(n);
  for (int k = 0; k < n; ++k) {
    const int row = static_cast<int>(idx[k] / cols), col = static_cast<int>(idx[k] % cols);
    out[k].r = {x0 + (col + (row % 2 ? 0.75 : 0.25)) * ax, y0 + (row + 0.5) * ay};
    out[k].radius = r;
  }
  return out;
}

void maxwell_velocities(std::vector<DiskInit>& disks, double kT, const Vec2& stream, bool rotation,
                        double q, core::Rng& rng) {
  const std::size_t n = disks.size();
  if (n == 0) return;
  Vec2 p{0.0, 0.0};
  double mt = 0.0;
  for (auto& d : disks) {
    const double s = std::sqrt(kT / d.mass);
    d.v = {s * rng.normal(), s * rng.normal()};
    p += d.mass * d.v;
    mt += d.mass;
  }
  const Vec2 vcm = p / mt;
  double k = 0.0;
  for (auto& d : disks) {
    d.v -= vcm;
    k += 0.5 * d.mass * d.v.squaredNorm();
  }
  const double scale = (n > 1 && k > 0.0) ? std::sqrt(static_cast<double>(n) * kT / k) : 0.0;
  for (auto& d : disks) {
    d.v = d.v * scale + stream;
    if (rotation) d.omega = std::sqrt(kT / (q * d.mass * d.radius * d.radius)) * rng.normal();
  }
}

}  // namespace grainflow::ed
