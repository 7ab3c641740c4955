// The cell map of the ED engine (seed 003 §2.2): a regular grid of cells no smaller than
// the largest diameter, each holding its disks in a short block of slots, so a disk only
// meets disks of its 3×3 neighbourhood; periodic axes wrap with an image shift.
#pragma once
#include <cstdint>
#include <vector>

#include "engine/ed/huge_pages.hpp"
#include "engine/ed/id24.hpp"

namespace grainflow::io {
class ArchiveWriter;
class ArchiveReader;
}  // namespace grainflow::io

namespace grainflow::ed {

class CellGrid {
public:
  CellGrid() = default;
  // Throws grainflow::Error when the box cannot hold cells of at least min_cell, or a
  // periodic axis would have fewer than 3 cells (the 9 neighbours must be distinct).
  // min_diameter: the smallest disk diameter (sets the per-cell capacity).
  CellGrid(double lx, double ly, bool periodic_x, bool periodic_y, double min_cell, double min_diameter = 1.0);

  int nx() const { return nx_; }
  int ny() const { return ny_; }
  int size() const { return nx_ * ny_; }
  double width() const { return w_; }
  double height() const { return h_; }
  double lx() const { return lx_; }
  double ly() const { return ly_; }
  bool periodic_x() const { return px_; }
  bool periodic_y() const { return py_; }
  int index(int ix, int iy) const { return iy * nx_ + ix; }
  // The row by a multiplication, not an integer division (the event loop asks it at every
  // event): floor((c + ½)/nx) is exact in doubles, its fraction being at least ½/nx away
  // from an integer, far above the rounding (cells number < 2^31).
  int ix(int c) const { return c - iy(c) * nx_; }
  int iy(int c) const { return static_cast<int>((c + 0.5) * inv_nx_); }
  // Cell of a point inside the box (clamped to the grid against round-off at the edges).
  int cell_of_point(double x, double y) const;

  // Shift to add to a disk of cell cj to see it from cell ci (minimum image by cell offsets).
  void image_shift(int ci, int cj, double& sx, double& sy) const {
    const int dcx = ix(cj) - ix(ci), dcy = iy(cj) - iy(ci);
    sx = (2 * dcx > nx_) ? -lx_ : (2 * dcx < -nx_) ? lx_ : 0.0;
    sy = (2 * dcy > ny_) ? -ly_ : (2 * dcy < -ny_) ? ly_ : 0.0;
    if (!px_) sx = 0.0;
    if (!py_) sy = 0.0;
  }

  // Membership: each cell stores its disks in a fixed-capacity block — a count byte, then
  // the members' slots — so a neighbourhood scan reads one short contiguous block per cell
  // instead of chasing a linked list. The capacity follows from Groemer's packing bound
  // for centres at least min_diameter apart in a cell (N ≤ 2A/(√3 d²) + P/(2d) + 1).
  // Slots are 3 bytes and blocks are not padded: a block of capacity 4 (one-diameter
  // cells) is 13 bytes, so the three cells of a row of the 3×3 block take 39 bytes and
  // mostly share one cache line, and the map costs 15.7 bytes a disk at η = 0.65 (19.3
  // with a 3-byte count in 16-byte blocks). Without the count (empty slots marked) the
  // scan must test each slot, which measured 4–8 % slower.
  static constexpr int kMaxDisks = 1 << 24;  // disk slots a 3-byte slot can name
  void resize_particles(int n) {
    check_disks(n);
    cell_.assign(n, -1);
  }
  // More disk slots, keeping the present ones (disks entering an open stream, §3.2–3.3).
  void grow_particles(int n) {
    check_disks(n);
    cell_.resize(n, -1);
  }
  void insert(int i, int c) {
    std::uint8_t* s = block(c);
    const int n = s[0];
    if (n >= cap_) overflow(c);
    cell_[i] = c;
    store_id24(s + 1 + kSlotBytes * n, i);
    s[0] = static_cast<std::uint8_t>(n + 1);
  }
  // The last member takes i's place. i's place is found in the cell's few slots, on the
  // line that is written anyway, rather than kept per disk: a per-disk place array costs
  // 4 bytes a disk and a cache miss for i's place and another for the last member's.
  void remove(int i) {
    std::uint8_t* s = block(cell_[i]);
    const int n = s[0];
    std::uint8_t* p = s + 1;
    while (load_id24(p) != i) p += kSlotBytes;  // i is a member: the search ends inside the cell
    store_id24(p, load_id24(s + 1 + kSlotBytes * (n - 1)));
    s[0] = static_cast<std::uint8_t>(n - 1);
    cell_[i] = -1;
  }
  // A cell's slot block as a scan reads it: the count, then the members.
  class Slots {
  public:
    Slots() {}  // unset (a scan's array of them is filled before it is read)
    explicit Slots(const std::uint8_t* p) : p_(p) {}
    int count() const { return p_[0]; }
    int member(int k) const { return load_id24(p_ + 1 + kSlotBytes * k); }
    const void* address() const { return p_; }

  private:
    const std::uint8_t* p_;
  };
  Slots cell_slots(int c) const { return Slots(slots_.data() + static_cast<std::size_t>(c) * stride_); }
  int count(int c) const { return cell_slots(c).count(); }
  int member(int c, int k) const { return cell_slots(c).member(k); }
  int capacity() const { return cap_; }
  int cell(int i) const { return cell_[i]; }
  // Cache hint (no effect on results): disk i's cell entry is about to be read.
  void prefetch_cell(int i) const { __builtin_prefetch(&cell_[i]); }
  // Cache hint (no effect on results): the member slots of the 3×3 block of cells around
  // cell c (three runs of three cells each).
  void prefetch_block(int c) const {
    block_rows(c, [this](int first, int last) {
      const char* a = reinterpret_cast<const char*>(cell_slots(first).address());
      const char* b = reinterpret_cast<const char*>(cell_slots(last).address()) + stride_ - 1;
      for (; a <= b; a += 64) __builtin_prefetch(a);
      __builtin_prefetch(b);
    });
  }
  // Cache hint (no effect on results): the three cells two steps from cell c towards `dir`
  // (0 +x, 1 −x, 2 +y, 3 −y), the row a crossing that way brings into a disk's 3×3 block.
  // No periodic wrap, as for prefetch_block.
  void prefetch_beyond(int c, int dir) const {
    const int x = ix(c), y = iy(c);
    for (int k = -1; k <= 1; ++k) {
      const int cx = dir == 0 ? x + 2 : dir == 1 ? x - 2 : x + k;
      const int cy = dir == 2 ? y + 2 : dir == 3 ? y - 2 : y + k;
      if (cx >= 0 && cx < nx_ && cy >= 0 && cy < ny_) __builtin_prefetch(cell_slots(index(cx, cy)).address());
    }
  }
  // Calls f(cc) for each cell of the 3×3 neighbourhood of cell c, wrapping periodic axes
  // and leaving out cells beyond a non-periodic edge. Periodic axes have at least 3 cells,
  // so the cells are distinct.
  template <class F>
  void for_neighbour_cells(int c, F&& f) const {
    for (int ky = -1; ky <= 1; ++ky) {
      int cy = iy(c) + ky;
      if (cy < 0 || cy >= ny_) {
        if (!py_) continue;
        cy = (cy + ny_) % ny_;
      }
      for (int kx = -1; kx <= 1; ++kx) {
        int cx = ix(c) + kx;
        if (cx < 0 || cx >= nx_) {
          if (!px_) continue;
          cx = (cx + nx_) % nx_;
        }
        f(index(cx, cy));
      }
    }
  }
  std::size_t memory_bytes() const { return slots_.capacity() + cell_.capacity() * 4; }

  // ---- checkpoints: the membership (the order of a cell's members is the order its
  // neighbourhood is scanned in, which decides ties) as 4-byte arrays — the blocks of
  // capacity + 1 slots, each disk's cell and each disk's place in its cell (derived, kept
  // for the archive's checks) —; the geometry is rebuilt from the configuration and only
  // compared.
  struct Members {
    HugeVector<std::int32_t> slots, cell, pos;
    HugeVector<std::uint8_t> packed;  // slots as the grid keeps them (read_members fills it)
  };
  void save_members(io::ArchiveWriter& w) const;
  // Reads what save_members wrote for n_disks disk slots; throws grainflow::Error (the
  // reader's mismatch) for another geometry or (corrupt) arrays of other sizes. Whether
  // the members agree with the disks' slot states is for the caller to check.
  Members read_members(io::ArchiveReader& r, int n_disks) const;
  // The membership as adopt_members takes it (a snapshot in memory: SystemState::snapshot).
  void copy_members(Members& m) const {
    m.packed = slots_;
    m.cell = cell_;
  }
  void adopt_members(Members&& m) noexcept {
    slots_.swap(m.packed);
    cell_.swap(m.cell);
  }

private:
  // Calls f(first, last) for each row of the 3×3 block around cell c: the cells first..last
  // of a row are adjacent in memory. Clamped at the grid's edges, no periodic wrap: the
  // callers are cache hints, for which a missed image cell costs only time.
  template <class F>
  void block_rows(int c, F&& f) const {
    const int x0 = ix(c) > 0 ? ix(c) - 1 : 0, x1 = ix(c) + 1 < nx_ ? ix(c) + 1 : nx_ - 1;
    const int y = iy(c);
    for (int yy = y > 0 ? y - 1 : 0; yy <= (y + 1 < ny_ ? y + 1 : ny_ - 1); ++yy) f(index(x0, yy), index(x1, yy));
  }

  int nx_ = 0, ny_ = 0;
  double inv_nx_ = 0.0;  // 1 / nx_ (iy)
  double w_ = 0.0, h_ = 0.0, lx_ = 0.0, ly_ = 0.0;
  bool px_ = false, py_ = false;
  void overflow(int c) const;  // throws: only overlapping disks can overfill a cell
  void check_disks(int n) const;  // throws beyond kMaxDisks
  // Slots are 3-byte ids; load_id24 reads 4 bytes, which the slack after the last block
  // allows.
  static constexpr int kSlotBytes = kId24Bytes;
  std::uint8_t* block(int c) { return slots_.data() + static_cast<std::size_t>(c) * stride_; }
  // The blocks as checkpoints keep them (capacity + 1 four-byte slots a cell), and back.
  HugeVector<std::int32_t> unpacked_slots() const;
  HugeVector<std::uint8_t> packed_slots(const HugeVector<std::int32_t>& unpacked) const;

  int cap_ = 0;
  std::size_t stride_ = 1;  // bytes a cell's block takes: the count byte and capacity slots
  static constexpr int kMaxCapacity = 255;  // what the count byte holds
  HugeVector<std::uint8_t> slots_;  // the blocks, then 4 bytes of slack
  HugeVector<std::int32_t> cell_;
};

}  // namespace grainflow::ed
