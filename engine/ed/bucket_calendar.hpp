// Event calendar with one scheduled event per entry in a bucket queue (Paul 2007, "A
// complexity O(1) priority queue for event driven molecular dynamics simulations",
// J. Comput. Phys. 221, 615) laid out in two tiers, as in a ladder queue (Tang, Goh &
// Thng 2005, ACM TOMACS 15, 175): a window of fine time buckets of width dt, grouped F at a
// time into coarse buckets; only the coarse bucket being processed is spread over its fine
// buckets, later events are appended unsorted to their coarse bucket, and events beyond the
// window to an overflow. A small binary heap orders the fine bucket being processed.
// Buckets are chains of arrays of entry ids (chunks from one pool), not linked lists of
// entries: at N ≳ 10^5 every list link an update touches is a cache miss (the old
// neighbours and the old head), while an append writes the end of a chunk that is in
// cache, and a bucket is read as a few contiguous arrays. Entries that move leave a stale copy behind
// (lazy deletion): where_[e] names the one bucket whose copy counts. Same interface as
// CellHeapCalendar, and the same order of events: the heap pops in the total order of
// (key, entry), whatever the layout of the buckets.
#pragma once
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/ed/calendar_keys.hpp"
#include "engine/ed/cell_grid.hpp"
#include "engine/ed/huge_pages.hpp"

namespace grainflow::ed {

class BucketCalendar {
public:
  static constexpr const char* kName = "bucket";

  // Tuning: expected events per fine bucket, window span in mean event intervals of an
  // entry, and fine buckets per coarse bucket, a power of two (a bucket's coarse bucket
  // and place in it are then a shift and a mask, not a 64-bit division, at every insert).
  explicit BucketCalendar(double events_per_bucket = 2.0, double span = 8.0, int fine_per_coarse = 512)
      : per_bucket_(events_per_bucket), span_(span), f_(fine_per_coarse), f_shift_(std::countr_zero(
                                                                              static_cast<unsigned>(fine_per_coarse))) {
    if (fine_per_coarse < 1 || !std::has_single_bit(static_cast<unsigned>(fine_per_coarse)))
      throw Error("ed: bucket calendar: fine buckets per coarse bucket must be a power of two, not " +
                  std::to_string(fine_per_coarse));
  }

  void reset(CalendarKeys key, const CellGrid* grid, int n_disks, int n_timers) {
    key_ = key;
    grid_ = grid;
    nd_ = n_disks;
    ne_ = n_disks + n_timers;
    const std::int64_t want = std::max<std::int64_t>(64, static_cast<std::int64_t>(span_ * ne_ / per_bucket_));
    nc_ = static_cast<std::int32_t>((want + f_ - 1) / f_);
    nb_ = static_cast<std::int64_t>(nc_) * f_;
    where_.assign(ne_, kParked);
    heap_.clear();
    heap_.reserve(64);
    pool_.clear();
    free_ = -1;
    // Buckets 0..F−1 are the fine ones, F..F+nc−1 the coarse ones, F+nc the overflow.
    bucket_.assign(static_cast<std::size_t>(overflow_id()) + 1, Bucket{});
    n_listed_ = 0;
    cur_ = 0;
    w0_ = 0;
    kcur_ = 0;
    // Everything starts in the overflow; rebuild() tunes dt and distributes it.
    for (int e = 0; e < ne_; ++e)
      if (std::isfinite(key_[e])) list_push(overflow_id(), e);
    rebuild();
  }

  void update(int e) {
    const double t = key_[e];
    if (where_[e] <= kHeap0 && std::isfinite(t) && bucket_of(t) <= cur_) {
      resift(heap_pos(e));  // stays in the near-future window: re-sift in place
      return;
    }
    detach(e);
    insert(e);
  }
  void moved(int, int, int) {}
  // Cache hint: entry e is about to be updated.
  void prefetch(int e) const { __builtin_prefetch(&where_[e]); }
  // Entry e's disk left the system (its key is already kNever).
  void removed(int e, int /*cell*/) { detach(e); }
  void commit() {}

  int top() {
    while (heap_.empty()) {
      if (n_listed_ == 0) return -1;
      ++cur_;
      const std::int64_t rel = cur_ - w0_;
      if (rel >= nb_) {
        rebuild();
        continue;
      }
      const std::int32_t s = fine_of(rel);
      if (s == 0) {
        kcur_ = coarse_of(rel);
        spread(kcur_);
      }
      dump(s);
    }
    return heap_[0];
  }

  double bucket_width() const { return dt_; }
  // The chunks counted are those ever handed out (the pool's high-water mark), not the
  // vector's capacity: its doubling reserve, up to as much again, is never touched.
  std::size_t memory_bytes() const {
    return (heap_.capacity() + scratch_.capacity() + where_.capacity()) * 4 + pool_.size() * sizeof(Chunk) +
           bucket_.capacity() * sizeof(Bucket);
  }

private:
  // where_[e]: the bucket holding e's live copy — a fine bucket 0..F−1 (of the coarse
  // bucket being processed), coarse bucket k as F + k, the overflow as F + nc — or kParked
  // (infinite key: nowhere), or heap position p as kHeap0 − p.
  static constexpr std::int32_t kParked = -1;
  static constexpr std::int32_t kHeap0 = -2;
  std::int32_t overflow_id() const { return f_ + nc_; }
  // Bucket rel ≥ 0 of the window: its coarse bucket, and its place in it.
  std::int32_t coarse_of(std::int64_t rel) const { return static_cast<std::int32_t>(rel >> f_shift_); }
  std::int32_t fine_of(std::int64_t rel) const { return static_cast<std::int32_t>(rel & (f_ - 1)); }
  int heap_pos(int e) const { return kHeap0 - where_[e]; }
  void set_heap_pos(int e, int p) { where_[e] = kHeap0 - p; }

  // floor(t / dt) without the libm call std::floor compiles to on baseline x86-64, and with
  // a multiplication: any bucket map monotone in t gives the same event order (entries of
  // one bucket are ordered by the heap), so rounding in 1/dt changes nothing.
  std::int64_t bucket_of(double t) const {
    const double q = t * inv_dt_;
    const auto b = static_cast<std::int64_t>(q);
    return b - (q < static_cast<double>(b));
  }
  bool less(int a, int b) const { return key_[a] < key_[b] || (key_[a] == key_[b] && a < b); }

  // Appends e to bucket `id` (a fine or coarse bucket, or the overflow).
  void list_push(std::int32_t id, int e) {
    Bucket& b = bucket_[static_cast<std::size_t>(id)];
    if (b.tail < 0 || b.n == kChunkIds) {
      const std::int32_t c = new_chunk();
      if (b.tail < 0) b.head = c; else pool_[static_cast<std::size_t>(b.tail)].next = c;
      b.tail = c;
      b.n = 0;
    }
    pool_[static_cast<std::size_t>(b.tail)].ids[b.n++] = e;
    where_[e] = id;
    ++n_listed_;
  }
  std::int32_t new_chunk() {
    std::int32_t c = free_;
    if (c >= 0) {
      free_ = pool_[static_cast<std::size_t>(c)].next;
    } else {
      c = static_cast<std::int32_t>(pool_.size());
      pool_.emplace_back();
    }
    pool_[static_cast<std::size_t>(c)].next = -1;
    return c;
  }
  // Calls f(e) for every id bucket `id` holds (stale copies included), then empties it
  // and returns its chunks to the pool. Each chunk's entries (their where_ and key, which
  // f reads: a miss each, at random) are prefetched together before f sees them.
  // hint_cells: also fetch each disk's cell entry (the bucket goes to the heap: its events
  // come next, and the loop starts each by reading the disk's cell).
  template <bool hint_cells = false, class F>
  void drain(std::int32_t id, F&& f) {
    const Bucket b = bucket_[static_cast<std::size_t>(id)];
    bucket_[static_cast<std::size_t>(id)] = Bucket{};
    for (std::int32_t c = b.head; c >= 0;) {
      // By index, not by reference: f may append to other buckets and so grow the pool.
      const std::size_t ci = static_cast<std::size_t>(c);
      const std::int32_t next = pool_[ci].next;
      if (next >= 0) __builtin_prefetch(&pool_[static_cast<std::size_t>(next)]);
      const int n = c == b.tail ? b.n : kChunkIds;
      for (int q = 0; q < n; ++q) {
        __builtin_prefetch(&where_[pool_[ci].ids[q]]);
        __builtin_prefetch(key_.at(pool_[ci].ids[q]));
        if constexpr (hint_cells)
          if (grid_ && pool_[ci].ids[q] < nd_) grid_->prefetch_cell(pool_[ci].ids[q]);
      }
      for (int q = 0; q < n; ++q) f(pool_[ci].ids[q]);
      pool_[ci].next = free_;
      free_ = c;
      c = next;
    }
  }
  void insert(int e) {
    const double t = key_[e];
    if (!std::isfinite(t)) { where_[e] = kParked; return; }
    const std::int64_t b = bucket_of(t);
    if (b <= cur_) { heap_push(e); return; }
    const std::int64_t rel = b - w0_;
    if (rel >= nb_) { list_push(overflow_id(), e); return; }
    const std::int32_t k = coarse_of(rel);
    list_push(k == kcur_ ? fine_of(rel) : f_ + k, e);
  }
  // Takes e out: from the heap at once, from a bucket lazily (its copy there turns stale).
  void detach(int e) {
    const std::int32_t w = where_[e];
    if (w == kParked) return;
    if (w <= kHeap0) {
      const int p = heap_pos(e);
      const int last = heap_.back();
      heap_.pop_back();
      if (last != e) {
        heap_[p] = last;
        set_heap_pos(last, p);
        resift(p);
      }
    } else {
      --n_listed_;
    }
    where_[e] = kParked;
  }

  // Coarse bucket k comes up: its live entries go to their fine buckets (or to the heap,
  // those of the current fine bucket).
  void spread(std::int32_t k) {
    const std::int32_t id = f_ + k;
    drain(id, [&](std::int32_t e) {
      if (where_[e] != id) return;  // stale copy
      --n_listed_;
      where_[e] = kParked;
      insert(e);
    });
  }
  // Fine bucket s comes up: its live entries go to the heap.
  void dump(std::int32_t s) {
    drain<true>(s, [&](std::int32_t e) {
      if (where_[e] != s) return;  // stale copy (or a second copy, already taken)
      --n_listed_;
      heap_push(e);
    });
  }

  // Called when the window is used up (so every scheduled entry sits in the overflow):
  // re-tune dt from the current spread of event times and lay out a new window.
  void rebuild() {
    scratch_.clear();
    double tmin = std::numeric_limits<double>::infinity();
    const std::int32_t id = overflow_id();
    drain(id, [&](std::int32_t e) {
      if (where_[e] != id) return;
      where_[e] = kParked;  // a second copy of e is now stale
      scratch_.push_back(e);
      tmin = std::min(tmin, key_[e]);
    });
    n_listed_ -= static_cast<std::int64_t>(scratch_.size());
    if (scratch_.empty()) return;
    // Sort the overflow by entry so the layout does not depend on list history.
    std::sort(scratch_.begin(), scratch_.end());
    double mean = 0.0;
    for (int e : scratch_) mean += key_[e] - tmin;
    mean /= static_cast<double>(scratch_.size());
    // n entries each firing about once per `mean` give n/mean events per unit time.
    double dt = per_bucket_ * mean / static_cast<double>(scratch_.size());
    if (!(dt > 0.0) || !std::isfinite(dt)) dt = dt_ > 0.0 ? dt_ : 1.0;
    // Keep bucket indices well inside int64 and dt above the spacing of doubles near tmin.
    dt = std::max(dt, std::abs(tmin) * 1e-13 + 1e-300);
    dt_ = dt;
    inv_dt_ = 1.0 / dt;
    cur_ = bucket_of(tmin);
    w0_ = cur_;
    kcur_ = 0;
    for (int e : scratch_) insert(e);
  }

  void heap_push(int e) {
    heap_.push_back(e);
    sift_up(static_cast<int>(heap_.size()) - 1);
  }
  // Restores the heap order around position p after its entry's key changed.
  void resift(int p) {
    if (p > 0 && less(heap_[p], heap_[(p - 1) / 2])) sift_up(p); else sift_down(p);
  }
  void sift_up(int p) {
    const int e = heap_[p];
    while (p > 0) {
      const int parent = (p - 1) / 2;
      if (!less(e, heap_[parent])) break;
      heap_[p] = heap_[parent];
      set_heap_pos(heap_[p], p);
      p = parent;
    }
    heap_[p] = e;
    set_heap_pos(e, p);
  }
  void sift_down(int p) {
    const int size = static_cast<int>(heap_.size());
    const int e = heap_[p];
    for (;;) {
      int c = 2 * p + 1;
      if (c >= size) break;
      if (c + 1 < size && less(heap_[c + 1], heap_[c])) ++c;
      if (!less(heap_[c], e)) break;
      heap_[p] = heap_[c];
      set_heap_pos(heap_[p], p);
      p = c;
    }
    heap_[p] = e;
    set_heap_pos(e, p);
  }

  double per_bucket_, span_;
  std::int32_t f_;  // fine buckets per coarse bucket
  int f_shift_;     // log2 f_
  CalendarKeys key_;
  const CellGrid* grid_ = nullptr;  // for cache hints only
  int ne_ = 0, nd_ = 0;
  std::int32_t nc_ = 0, kcur_ = 0;  // coarse buckets in the window; the one being processed
  std::int64_t nb_ = 0, cur_ = 0, w0_ = 0, n_listed_ = 0;
  double dt_ = 0.0, inv_dt_ = 0.0;
  HugeVector<std::int32_t> where_;
  // A bucket is a chain of chunks, appended at the tail; empty chunks form the free list.
  // One cache line per chunk; a bucket keeps the fill of its tail chunk (the others are
  // full), so an append writes only the tail chunk.
  static constexpr int kChunkIds = 15;
  struct alignas(64) Chunk {
    std::int32_t next;
    std::int32_t ids[kChunkIds];
  };
  struct Bucket {
    std::int32_t head = -1, tail = -1, n = 0;
  };
  HugeVector<Chunk> pool_;
  std::int32_t free_ = -1;
  std::vector<Bucket> bucket_;
  std::vector<std::int32_t> heap_, scratch_;
};

}  // namespace grainflow::ed
