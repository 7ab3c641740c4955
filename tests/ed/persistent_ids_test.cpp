// Persistent disk ids (ed::SystemState::tag), what particle files write as `id`: a disk
// keeps its id while it is in the system, whatever happens to the memory slot it sits in;
// a newcomer of an open stream gets an id never used before, even in the slot of a disk
// that left. Followed by id, a trajectory therefore never jumps.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <map>
#include <memory>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "engine/core/error.hpp"
#include "engine/ed/dense_stream.hpp"
#include "engine/ed/low_density_stream.hpp"
#include "engine/ed/simulation.hpp"

namespace ed = grainflow::ed;

namespace {

struct Seen {
  double x, y;
};

// id → position now of every disk present; fails on an id given to two disks.
std::map<std::int64_t, Seen> by_id(ed::Simulation& sim) {
  sim.synchronise();
  std::map<std::int64_t, Seen> out;
  for (int i = 0; i < sim.size(); ++i) {
    if (!sim.present(i)) continue;
    EXPECT_GT(sim.tag(i), 0) << "slot " << i;
    const bool fresh = out.emplace(sim.tag(i), Seen{sim.disks()[i].x, sim.disks()[i].y}).second;
    EXPECT_TRUE(fresh) << "id " << sim.tag(i) << " is held by two disks";
  }
  return out;
}

// Runs `sim` in steps of dt up to t_end and checks, between consecutive looks, that every
// disk seen both times moved less than max_step (the slot of a disk that left and was
// refilled would show as a jump across the channel under a slot-based id), that an id
// that disappeared never comes back, and that every newcomer's id is above all ids seen
// before (y periodic: steps are taken between nearest images). Returns how many slots were refilled with a newcomer.
int follow(ed::Simulation& sim, double dt, double t_end, double max_step) {
  auto before = by_id(sim);
  std::map<int, std::int64_t> slot_tag;  // the id each slot held last time
  for (int i = 0; i < sim.size(); ++i)
    if (sim.present(i)) slot_tag[i] = sim.tag(i);
  std::set<std::int64_t> gone;
  std::int64_t highest = before.empty() ? 0 : before.rbegin()->first;
  int refilled = 0;
  double largest = 0;
  for (double t = sim.time() + dt; t <= t_end + 1e-9; t += dt) {
    sim.run_until(t);
    auto now = by_id(sim);
    for (int i = 0; i < sim.size(); ++i) {
      if (!sim.present(i)) continue;
      auto it = slot_tag.find(i);
      if (it != slot_tag.end() && it->second != sim.tag(i) && !now.count(it->second)) ++refilled;
      slot_tag[i] = sim.tag(i);
    }
    std::int64_t new_highest = highest;
    for (const auto& [id, p] : now) {
      EXPECT_FALSE(gone.count(id)) << "id " << id << " left and came back at t = " << t;
      if (auto b = before.find(id); b != before.end()) {
        // y is periodic: the shortest image.
        const double ly = sim.config().ly, dy = p.y - b->second.y;
        const double step = std::hypot(p.x - b->second.x, dy - ly * std::round(dy / ly));
        largest = std::max(largest, step);
        EXPECT_LT(step, max_step) << "id " << id << " jumped at t = " << t;
      } else {
        EXPECT_GT(id, highest) << "a newcomer got an id already given, at t = " << t;
        new_highest = std::max(new_highest, id);
      }
    }
    for (const auto& [id, p] : before)
      if (!now.count(id)) gone.insert(id);
    highest = new_highest;
    before = std::move(now);
  }
  std::printf("  %zu disks left, %d slots refilled by newcomers, largest step %.3g\n", gone.size(), refilled, largest);
  EXPECT_GT(gone.size(), 0u);
  EXPECT_EQ(sim.state().next_tag(), highest + 1);
  return refilled;
}

}  // namespace

TEST(PersistentIds, LowDensityStreamNewcomersGetNewIdsInRecycledSlots) {
  ed::Config c;
  c.lx = 30.0;
  c.ly = 20.0;
  c.area_fraction = 0.05;
  c.kT = 0.1;
  c.stream = {0.5, 0.0};
  c.periodic_x = false;
  c.open_x = true;
  c.seed = 3;
  ed::Simulation sim(c);
  ed::LowDensityStreamConfig lc;
  lc.U = 0.5;
  lc.kT = 0.1;
  lc.number_density = 0.05 / (std::numbers::pi / 4);
  lc.x_in = 1.0;
  lc.x_out = 29.0;
  ed::add_low_density_stream(sim, lc);
  // Free flight at |v| ≲ U + 5 sqrt(kT) ≈ 2.1 for dt = 0.5: ≈ 1; a refilled slot would jump ≈ 28.
  EXPECT_GT(follow(sim, 0.5, 200.0, 3.0), 20);
}

TEST(PersistentIds, DenseStreamDispenserAndFilterKeepIds) {
  ed::Config c;
  c.lx = 30.0;
  c.ly = 12.0;
  c.area_fraction = 0.65;
  c.kT = 0.02;
  c.stream = {0.5, 0.0};
  c.periodic_x = false;
  c.open_x = true;
  c.seed = 4;
  ed::Simulation sim(c);
  ed::DenseStreamConfig dc;
  dc.U = 0.5;
  dc.kT = 0.02;
  dc.filter_distance = 3.0;
  dc.seed = 6;
  ed::add_dense_stream(sim, dc);
  // At η = 0.65 a disk moves ≈ U dt = 0.25 in dt = 0.5 (frozen ones at U).
  EXPECT_GT(follow(sim, 0.5, 150.0, 1.5), 20);
}

TEST(PersistentIds, RenumberingSlotsKeepsEveryDisksId) {
  ed::Config c;
  c.lx = 20.0;
  c.ly = 20.0;
  c.area_fraction = 0.5;
  c.seed = 9;
  ed::Simulation sim(c);
  sim.run_until(3.0);
  const auto before = by_id(sim);
  // Shuffle the slots (reverse cell order), then drop a third of the disks.
  auto order = sim.cell_order();
  std::reverse(order.begin(), order.end());
  sim.reorder_disks(order);
  sim.remove_disks_unless([&](int i) { return sim.tag(i) % 3 != 0; });
  const auto after = by_id(sim);
  ASSERT_EQ(after.size(), before.size() - before.size() / 3);
  for (const auto& [id, p] : after) {
    ASSERT_TRUE(before.count(id)) << id;
    EXPECT_EQ(p.x, before.at(id).x);
    EXPECT_EQ(p.y, before.at(id).y);
    EXPECT_NE(id % 3, 0);
  }
  EXPECT_EQ(sim.state().next_tag(), std::int64_t(before.size()) + 1);
}

TEST(PersistentIds, GivenIdsAreKeptAndCheckedOtherwiseNumberedInOrder) {
  ed::Config c;
  c.lx = 10.0;
  c.ly = 10.0;
  auto disk = [](double x, double y, std::int64_t tag) {
    ed::DiskInit d;
    d.r = {x, y};
    d.tag = tag;
    return d;
  };
  {
    ed::Simulation sim(c, {disk(2, 2, 0), disk(5, 5, 0), disk(8, 8, 0)});
    EXPECT_EQ(sim.tag(0), 1);
    EXPECT_EQ(sim.tag(2), 3);
    EXPECT_EQ(sim.state().next_tag(), 4);
  }
  {
    ed::Simulation sim(c, {disk(2, 2, 70), disk(5, 5, 7), disk(8, 8, 12)});
    EXPECT_EQ(sim.tag(0), 70);
    EXPECT_EQ(sim.tag(1), 7);
    EXPECT_EQ(sim.state().next_tag(), 71);
  }
  auto refused = [&](std::vector<ed::DiskInit> d, const std::string& what) {
    try {
      ed::Simulation sim(c, std::move(d));
      ADD_FAILURE() << "accepted; expected: " << what;
    } catch (const grainflow::Error& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  refused({disk(2, 2, 5), disk(5, 5, 0)}, "1 of 2 disks have an id");
  refused({disk(2, 2, 5), disk(5, 5, 5)}, "disks 0 and 1 have the same id 5");
  refused({disk(2, 2, -1), disk(5, 5, 3)}, "disk 0 has id -1");
}
