// The ED cell map (seed 003 §2.2): membership under insert/remove against a plain model,
// the 3-byte slots at every byte boundary of an id, the block size they give, and the
// limit on disk slots.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/ed/cell_grid.hpp"

namespace ed = grainflow::ed;

namespace {

// What the grid must hold: each cell's members in order, the last one taking the place
// of a member removed (the scan order decides ties between equal event times).
struct Model {
  std::vector<std::vector<int>> cells;
  std::vector<int> cell_of;
  void insert(int i, int c) {
    cells[static_cast<std::size_t>(c)].push_back(i);
    cell_of[static_cast<std::size_t>(i)] = c;
  }
  void remove(int i) {
    auto& m = cells[static_cast<std::size_t>(cell_of[static_cast<std::size_t>(i)])];
    *std::find(m.begin(), m.end(), i) = m.back();
    m.pop_back();
    cell_of[static_cast<std::size_t>(i)] = -1;
  }
};

void expect_same(const ed::CellGrid& g, const Model& m, const std::vector<int>& ids) {
  for (int c = 0; c < g.size(); ++c) {
    const auto& want = m.cells[static_cast<std::size_t>(c)];
    ASSERT_EQ(g.count(c), static_cast<int>(want.size())) << "cell " << c;
    const ed::CellGrid::Slots s = g.cell_slots(c);
    ASSERT_EQ(s.count(), g.count(c));
    for (int k = 0; k < g.count(c); ++k) {
      EXPECT_EQ(g.member(c, k), want[static_cast<std::size_t>(k)]) << "cell " << c << " place " << k;
      EXPECT_EQ(s.member(k), want[static_cast<std::size_t>(k)]);
    }
  }
  for (int i : ids) EXPECT_EQ(g.cell(i), m.cell_of[static_cast<std::size_t>(i)]) << "disk " << i;
}

}  // namespace

TEST(CellGrid, KeepsMembershipThroughInsertsAndRemovals) {
  // 6 × 5 cells of width 1 for disks of diameter 1: capacity 4 a cell.
  ed::CellGrid g(6.0, 5.0, true, false, 1.0);
  ASSERT_EQ(g.capacity(), 4);
  // Ids whose bytes cross every boundary of a 3-byte slot, up to the largest one.
  const std::vector<int> ids = {0, 1, 254, 255, 256, 257, 65535, 65536, 65537, 70000, 1 << 20,
                                (1 << 23) - 1, 1 << 23, ed::CellGrid::kMaxDisks - 2, ed::CellGrid::kMaxDisks - 1};
  g.resize_particles(ed::CellGrid::kMaxDisks);
  Model m{std::vector<std::vector<int>>(static_cast<std::size_t>(g.size())),
          std::vector<int>(static_cast<std::size_t>(ed::CellGrid::kMaxDisks), -1)};
  std::mt19937 rng(7);
  std::vector<int> in, out = ids;
  for (int step = 0; step < 4000; ++step) {
    const bool add = !out.empty() && (in.empty() || rng() % 2 == 0);
    if (add) {
      const std::size_t k = rng() % out.size();
      const int i = out[k];
      int c = static_cast<int>(rng() % static_cast<unsigned>(g.size()));
      // Fill a few cells to capacity, where the last slot of a block borders the next block.
      if (step % 3 == 0) c = static_cast<int>(rng() % 3);
      if (g.count(c) == g.capacity()) continue;
      g.insert(i, c);
      m.insert(i, c);
      out.erase(out.begin() + static_cast<std::ptrdiff_t>(k));
      in.push_back(i);
    } else {
      const std::size_t k = rng() % in.size();
      const int i = in[k];
      g.remove(i);
      m.remove(i);
      in.erase(in.begin() + static_cast<std::ptrdiff_t>(k));
      out.push_back(i);
    }
    if (step % 97 == 0) expect_same(g, m, ids);
  }
  expect_same(g, m, ids);
}

TEST(CellGrid, OneDiameterCellsTakeThirteenBytes) {
  // Capacity 4: a count byte and four 3-byte slots, unpadded (16 bytes with a 3-byte count
  // and padding, 20 with 4-byte slots), so the three cells of a scanned row take 39 bytes.
  ed::CellGrid g(40.0, 30.0, true, true, 1.0);
  ASSERT_EQ(g.capacity(), 4);
  g.resize_particles(1000);
  EXPECT_EQ(g.memory_bytes(), static_cast<std::size_t>(g.size()) * 13 + 4 + 1000 * 4);
}

TEST(CellGrid, RefusesCellsOfMoreDisksThanTheCountByteHolds) {
  // Cells set by a diameter of 1 and disks down to 1/20 of it: about 470 disks could crowd
  // into one cell.
  EXPECT_NO_THROW(ed::CellGrid(40.0, 30.0, true, true, 1.0, 0.1));
  try {
    ed::CellGrid(40.0, 30.0, true, true, 1.0, 0.05);
    ADD_FAILURE() << "no error";
  } catch (const grainflow::Error& e) {
    EXPECT_NE(std::string(e.what()).find("at most about 14 times"), std::string::npos) << e.what();
  }
}

TEST(CellGrid, RefusesMoreDiskSlotsThanASlotCanName) {
  ed::CellGrid g(6.0, 5.0, true, true, 1.0);
  EXPECT_NO_THROW(g.resize_particles(100));
  EXPECT_THROW(g.resize_particles(ed::CellGrid::kMaxDisks + 1), grainflow::Error);
  EXPECT_THROW(g.grow_particles(ed::CellGrid::kMaxDisks + 1), grainflow::Error);
  try {
    g.grow_particles(ed::CellGrid::kMaxDisks + 1);
  } catch (const grainflow::Error& e) {
    EXPECT_NE(std::string(e.what()).find("16777216"), std::string::npos) << e.what();
  }
  // The grid is left as it was.
  EXPECT_EQ(g.cell(99), -1);
}
