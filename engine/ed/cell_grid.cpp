#include "engine/ed/cell_grid.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "engine/core/error.hpp"
#include "engine/io/archive.hpp"

namespace grainflow::ed {

CellGrid::CellGrid(double lx, double ly, bool periodic_x, bool periodic_y, double min_cell, double min_diameter)
    : lx_(lx), ly_(ly), px_(periodic_x), py_(periodic_y) {
  if (!(min_cell > 0.0) || !std::isfinite(min_cell))
    throw Error(fmt::format("ed: cell size {} is invalid; it must be a positive number no smaller "
                            "than the largest disk diameter", min_cell));
  nx_ = static_cast<int>(std::floor(lx / min_cell));
  ny_ = static_cast<int>(std::floor(ly / min_cell));
  const int need_x = px_ ? 3 : 1, need_y = py_ ? 3 : 1;
  if (nx_ < need_x || ny_ < need_y)
    throw Error(fmt::format("ed: box {} x {} holds {} x {} cells of size >= {}; needed at least {} x {} "
                            "(3 along a periodic axis) — enlarge the box",
                            lx, ly, nx_, ny_, min_cell, need_x, need_y));
  w_ = lx / nx_;
  h_ = ly / ny_;
  inv_nx_ = 1.0 / nx_;
  const double d = min_diameter;
  if (!(d > 0.0)) throw Error(fmt::format("ed: smallest disk diameter {} must be positive", d));
  const double cap = std::floor(2.0 * w_ * h_ / (std::sqrt(3.0) * d * d) + (w_ + h_) / d + 1.0);
  if (!(cap <= kMaxCapacity))
    throw Error(fmt::format("ed: cells of {} x {} for disks of diameter down to {} could hold {} disks, more "
                            "than the {} a cell can list — the largest diameter (which sets the cell size) may "
                            "be at most about 14 times the smallest",
                            w_, h_, d, cap, kMaxCapacity));
  cap_ = static_cast<int>(cap);
  stride_ = 1 + static_cast<std::size_t>(kSlotBytes) * cap_;
  slots_.assign(static_cast<std::size_t>(nx_) * ny_ * stride_ + 4, 0);
}

void CellGrid::check_disks(int n) const {
  if (n > kMaxDisks)
    throw Error(fmt::format("ed: {} disk slots asked for; the cell map names at most {} (3-byte slots)", n, kMaxDisks));
}

HugeVector<std::int32_t> CellGrid::unpacked_slots() const {
  HugeVector<std::int32_t> out(static_cast<std::size_t>(size()) * (cap_ + 1), 0);
  for (int c = 0; c < size(); ++c) {
    std::int32_t* o = &out[static_cast<std::size_t>(c) * (cap_ + 1)];
    o[0] = count(c);
    for (int k = 0; k < o[0]; ++k) o[1 + k] = member(c, k);
  }
  return out;
}

HugeVector<std::uint8_t> CellGrid::packed_slots(const HugeVector<std::int32_t>& unpacked) const {
  // Counts and ids out of range can only come from a corrupt archive, which the caller's
  // checks of the 4-byte arrays refuse; they are clamped here only to stay inside the blocks.
  HugeVector<std::uint8_t> out(slots_.size(), 0);
  for (int c = 0; c < size(); ++c) {
    const std::int32_t* b = &unpacked[static_cast<std::size_t>(c) * (cap_ + 1)];
    const int n = std::clamp(b[0], 0, cap_);
    std::uint8_t* o = out.data() + static_cast<std::size_t>(c) * stride_;
    o[0] = static_cast<std::uint8_t>(n);
    for (int k = 1; k <= n; ++k) store_id24(o + 1 + kSlotBytes * (k - 1), b[k] >= 0 && b[k] < kMaxDisks ? b[k] : 0);
  }
  return out;
}

void CellGrid::overflow(int c) const {
  throw Error(fmt::format("ed: cell ({}, {}) would hold more than {} disks, which only overlapping "
                          "disks can do; check the initial positions", ix(c), iy(c), cap_));
}

int CellGrid::cell_of_point(double x, double y) const {
  const int ix = std::clamp(static_cast<int>(std::floor(x / w_)), 0, nx_ - 1);
  const int iy = std::clamp(static_cast<int>(std::floor(y / h_)), 0, ny_ - 1);
  return index(ix, iy);
}

void CellGrid::save_members(io::ArchiveWriter& w) const {
  w.pod(static_cast<std::int32_t>(nx_));
  w.pod(static_cast<std::int32_t>(ny_));
  w.pod(static_cast<std::int32_t>(cap_));
  const HugeVector<std::int32_t> slots = unpacked_slots();
  w.array(slots);
  w.array(cell_);
  HugeVector<std::int32_t> pos(cell_.size(), -1);
  for (std::size_t b = 0; b < slots.size(); b += static_cast<std::size_t>(cap_ + 1))
    for (int k = 0; k < slots[b]; ++k) pos[static_cast<std::size_t>(slots[b + 1 + k])] = k;
  w.array(pos);
}

CellGrid::Members CellGrid::read_members(io::ArchiveReader& r, int n_disks) const {
  const auto nx = r.get<std::int32_t>(), ny = r.get<std::int32_t>(), cap = r.get<std::int32_t>();
  if (nx != nx_ || ny != ny_ || cap != cap_)
    r.mismatch(fmt::format("the cell grid has {} x {} cells of up to {} disks in the archive, {} x {} of up to {} "
                           "here (another box, cell size or disk diameter)",
                           nx, ny, cap, nx_, ny_, cap_));
  Members m;
  r.array_of(m.slots, static_cast<std::size_t>(size()) * (cap_ + 1), "the cell slot blocks");
  r.array_of(m.cell, static_cast<std::size_t>(n_disks), "the disks' cells");
  r.array_of(m.pos, static_cast<std::size_t>(n_disks), "the disks' places in their cells");
  m.packed = packed_slots(m.slots);
  return m;
}

}  // namespace grainflow::ed
