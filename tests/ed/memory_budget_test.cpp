// The ED state's hot working set (seed 003 §2.4 performance; the issue on 10^6 disks asks
// for at most 80 bytes a disk): what the event loop of the equilibrium box touches —
// disk records, event records, counters, the cell map and the calendar at its high-water
// mark — measured after the calendar has gone through several windows, and the arrays that
// box never reads counted as cold.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "engine/ed/simulation.hpp"
#include "tests/ed/periodic_box.hpp"

namespace ed = grainflow::ed;

TEST(EdMemory, PlainBoxTouchesAtMostEightyBytesPerDisk) {
  const int n = 40000;
  ed::Config c = ed::test::periodic_box(n, 0.65, 3);
  c.calendar = ed::CalendarKind::bucket;
  ed::Simulation sim(c);
  // Melting the lattice and 20 collisions a disk more: each entry's window spans about
  // 8 of its events, so the calendar's pool has been through several windows.
  while (sim.stats().collisions < 30ull * n) sim.advance(100000);
  double hot = 0.0;
  std::set<std::string> hot_parts;
  for (const auto& p : sim.memory_parts())
    if (p.hot) {
      hot += static_cast<double>(p.bytes);
      hot_parts.insert(p.name);
    }
  EXPECT_LE(hot / n, 80.0);
  EXPECT_GT(hot / n, 60.0);  // disk 32 + event 16 + counter 4 + cells ≥ 10: nothing left out
  EXPECT_EQ(hot_parts, (std::set<std::string>{"disk records", "event records", "counters", "cell map", "calendar"}));
}
