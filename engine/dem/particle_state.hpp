// Per-particle arrays of the DEM engine (structure of arrays, xyz packed per particle)
// and the simulation box with its flat walls (seed 000 §2.1–2.2). SI units.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace grainflow::dem {

struct Particles {
  std::size_t n = 0;
  std::vector<double> x;      // 3n positions [m]
  std::vector<double> v;      // 3n velocities at the half step n−1/2 [m/s] (leap-frog)
  std::vector<double> w;      // 3n angular velocities at the half step [rad/s]
  std::vector<double> f;      // 3n total force of the last force evaluation [N]
  std::vector<double> t;      // 3n total torque [N m]
  std::vector<double> radius, mass, inv_mass, inv_inertia;
  std::vector<std::uint8_t> group;

  void resize(std::size_t count) {
    n = count;
    x.assign(3 * n, 0.0);
    v.assign(3 * n, 0.0);
    w.assign(3 * n, 0.0);
    f.assign(3 * n, 0.0);
    t.assign(3 * n, 0.0);
    radius.assign(n, 0.0);
    mass.assign(n, 0.0);
    inv_mass.assign(n, 0.0);
    inv_inertia.assign(n, 0.0);
    group.assign(n, 0);
  }
};

// Wall w = 2·axis + side (side 0 at lo, 1 at hi). A wall exists on every non-periodic
// side except the top (z hi) of an open box.
struct Box {
  double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1}, len[3] = {1, 1, 1};
  bool periodic[3] = {false, false, false};
  bool wall[6] = {true, true, true, true, true, true};
  double wall_vel[6][3] = {};  // in-plane wall velocity [m/s] (plane Couette)
  // The 27 image shifts, code s = sx + 3 sy + 9 sz with s_a ∈ {0: −L, 1: 0, 2: +L}.
  double shift[27][3] = {};

  void finalize() {
    for (int a = 0; a < 3; ++a) len[a] = hi[a] - lo[a];
    for (int s = 0; s < 27; ++s) {
      const int c[3] = {s % 3, (s / 3) % 3, s / 9};
      for (int a = 0; a < 3; ++a) shift[s][a] = (c[a] - 1) * len[a];
    }
  }
  static constexpr int kNoShift = 13;
};

}  // namespace grainflow::dem
