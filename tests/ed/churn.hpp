// Random changes to the set of disks, for tests of the open-system bookkeeping (slots,
// cell lists, calendar, checkpoints): removes a random present disk, adds `adds` disks at
// random free places (no overlap, periodic images included) and freezes one every seventh
// action, all from the caller's random stream.
#pragma once
#include <cmath>
#include <cstdint>

#include "engine/core/rng.hpp"
#include "engine/ed/system_state.hpp"

namespace grainflow::ed::test {

inline void churn(SystemState& s, core::Rng& rng, std::int64_t action, int adds) {
  if (s.count() > 4) {
    int i;
    do i = int(rng.below(std::uint64_t(s.size()))); while (!s.present(i));
    s.remove_disk(i);
  }
  for (int a = 0; a < adds; ++a) {
    for (int tries = 0; tries < 1000; ++tries) {
      DiskInit d;
      d.r = {rng.uniform() * s.grid.lx(), rng.uniform() * s.grid.ly()};
      bool free = true;
      for (int j = 0; j < s.size() && free; ++j) {
        if (!s.present(j)) continue;
        Vec2 dr = s.position_now(j) - d.r;
        dr.x() -= s.grid.lx() * std::round(dr.x() / s.grid.lx());
        dr.y() -= s.grid.ly() * std::round(dr.y() / s.grid.ly());
        free = dr.norm() > 1.0 + 1e-6;
      }
      if (!free) continue;
      d.v = {rng.normal(), rng.normal()};
      s.add_disk(d);
      break;
    }
  }
  if (action % 7 == 0) {
    int i;
    do i = int(rng.below(std::uint64_t(s.size()))); while (!s.present(i));
    s.freeze(i, 0.3 * rng.normal(), 0.3 * rng.normal());
  }
}

}  // namespace grainflow::ed::test
