// Event calendar of seed 003 §2.4: a binary heap whose entries are cells (plus one node per
// timer agent); each cell node carries the earliest event among its disks. Disks whose
// event changes only tag their cell; commit() rescans tagged cells and re-sifts them.
#pragma once
#include <cstdint>
#include <limits>
#include <vector>

#include "engine/ed/calendar_keys.hpp"
#include "engine/ed/cell_grid.hpp"
#include "engine/ed/huge_pages.hpp"

namespace grainflow::ed {

class CellHeapCalendar {
public:
  static constexpr const char* kName = "cell_heap";

  // key[e] is the absolute time of entry e's next event: disks are entries 0..n_disks-1,
  // timer agents n_disks..n_disks+n_timers-1 (calendar_keys.hpp).
  void reset(CalendarKeys key, const CellGrid* grid, int n_disks, int n_timers) {
    key_ = key;
    grid_ = grid;
    nd_ = n_disks;
    nc_ = grid->size();
    const int nodes = nc_ + n_timers;
    bt_.assign(nodes, kInf);
    be_.assign(nodes, kNone);
    dirty_flag_.assign(nodes, 0);
    dirty_.clear();
    heap_.resize(nodes);
    pos_.resize(nodes);
    for (int n = 0; n < nodes; ++n) {
      recompute(n);
      heap_[n] = n;
      pos_[n] = n;
    }
    for (int k = nodes / 2 - 1; k >= 0; --k) sift_down(k);
  }

  void update(int e) { mark(e < nd_ ? grid_->cell(e) : nc_ + (e - nd_)); }
  void moved(int /*disk*/, int from_cell, int to_cell) {
    mark(from_cell);
    mark(to_cell);
  }
  // Disk e left the system from `cell` (no longer in the cell map).
  void removed(int /*e*/, int cell) { mark(cell); }
  void commit() {
    for (int n : dirty_) {
      dirty_flag_[n] = 0;
      recompute(n);
      const int p = pos_[n];
      if (p > 0 && less(n, heap_[(p - 1) / 2])) sift_up(p); else sift_down(p);
    }
    dirty_.clear();
  }
  // Entry with the earliest (time, entry) key, or −1 when nothing is scheduled.
  int top() const { return bt_[heap_[0]] == kInf ? -1 : be_[heap_[0]]; }
  std::size_t memory_bytes() const {
    return bt_.capacity() * 8 + (be_.capacity() + heap_.capacity() + pos_.capacity()) * 4 +
           dirty_flag_.capacity();
  }

private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  static constexpr int kNone = std::numeric_limits<int>::max();

  void mark(int n) {
    if (!dirty_flag_[n]) {
      dirty_flag_[n] = 1;
      dirty_.push_back(n);
    }
  }
  void recompute(int n) {
    double bt = kInf;
    int be = kNone;
    if (n < nc_) {
      const CellGrid::Slots m = grid_->cell_slots(n);
      for (int k = 0, cnt = m.count(); k < cnt; ++k) {
        const int i = m.member(k);
        const double t = key_[i];
        if (t < bt || (t == bt && i < be)) { bt = t; be = i; }
      }
    } else {
      be = nd_ + (n - nc_);
      bt = key_[be];
    }
    bt_[n] = bt;
    be_[n] = be;
  }
  bool less(int a, int b) const { return bt_[a] < bt_[b] || (bt_[a] == bt_[b] && be_[a] < be_[b]); }
  void sift_up(int p) {
    const int n = heap_[p];
    while (p > 0) {
      const int parent = (p - 1) / 2;
      if (!less(n, heap_[parent])) break;
      heap_[p] = heap_[parent];
      pos_[heap_[p]] = p;
      p = parent;
    }
    heap_[p] = n;
    pos_[n] = p;
  }
  void sift_down(int p) {
    const int size = static_cast<int>(heap_.size());
    const int n = heap_[p];
    for (;;) {
      int c = 2 * p + 1;
      if (c >= size) break;
      if (c + 1 < size && less(heap_[c + 1], heap_[c])) ++c;
      if (!less(heap_[c], n)) break;
      heap_[p] = heap_[c];
      pos_[heap_[p]] = p;
      p = c;
    }
    heap_[p] = n;
    pos_[n] = p;
  }

  CalendarKeys key_;
  const CellGrid* grid_ = nullptr;
  int nd_ = 0, nc_ = 0;
  HugeVector<double> bt_;  // best time per node
  HugeVector<int> be_;     // best entry per node
  HugeVector<int> heap_, pos_;
  std::vector<std::uint8_t> dirty_flag_;
  std::vector<int> dirty_;
};

}  // namespace grainflow::ed
