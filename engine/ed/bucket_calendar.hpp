// Event calendar with one scheduled event per entry in a bucket queue (Paul 2007, "A
// complexity O(1) priority queue for event driven molecular dynamics simulations",
// J. Comput. Phys. 221, 615) laid out in two tiers, as in a ladder queue (Tang, Goh &
// Thng 2005, ACM TOMACS 15, 175): a window of fine time buckets of width dt, grouped F at a
// time into coarse buckets; only the coarse bucket being processed is spread over its fine
// buckets (in a lane of the parallel loop, the next one too, a chunk at a time while the
// lane waits: see spread_ahead), later events are appended unsorted to their coarse
// bucket, and events beyond the window to an overflow. A small binary heap orders the
// fine bucket being processed.
// Buckets are chains of arrays of entry ids (chunks from one pool), not linked lists of
// entries: at N ≳ 10^5 every list link an update touches is a cache miss (the old
// neighbours and the old head), while an append writes the end of a chunk that is in
// cache, and a bucket is read as a few contiguous arrays.
// Deletion is lazy everywhere, and the calendar keeps nothing per entry: an update appends
// a new copy and leaves the old one behind. Whether a copy counts follows from the entry's
// key alone — a bucket's copy counts when the key falls in that bucket, a heap copy (which
// carries its key) when the key is still the one it carries — so stale copies are dropped
// when their bucket comes up, and a live entry's copies all sit in one place (duplicates
// there are harmless: the heap pops them in turn, and the second is stale by then unless
// the entry was re-scheduled to the very same time, which is then its event). Keeping a
// per-entry location instead costs 4 bytes a disk and a cache miss at every update.
// Same interface as CellHeapCalendar, and the same order of events: the heap pops in the
// total order of (key, entry), whatever the layout of the buckets.
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
#include "engine/ed/id24.hpp"

namespace grainflow::ed {

class BucketCalendar {
public:
  static constexpr const char* kName = "bucket";
  static constexpr int kMaxEntries = 1 << 24;

  // Tuning: expected events per fine bucket, window span in mean event intervals of an
  // entry, and fine buckets per coarse bucket at most, a power of two (a bucket's coarse
  // bucket and place in it are then a shift and a mask, not a 64-bit division, at every
  // insert). Fewer fine buckets are used for fewer than 64 entries a fine bucket: each
  // fine bucket in use holds a chunk of its own, a cache line for about two entries.
  static constexpr double kPerBucket = 2.0, kSpan = 8.0;
  static constexpr int kFinePerCoarse = 512;
  explicit BucketCalendar(double events_per_bucket = kPerBucket, double span = kSpan,
                          int fine_per_coarse = kFinePerCoarse)
      : per_bucket_(events_per_bucket), span_(span), max_f_(fine_per_coarse) {
    if (fine_per_coarse < 1 || !std::has_single_bit(static_cast<unsigned>(fine_per_coarse)))
      throw Error("ed: bucket calendar: fine buckets per coarse bucket must be a power of two, not " +
                  std::to_string(fine_per_coarse));
  }
  // The calendar of a lane of the parallel loop: the next coarse bucket may be spread ahead,
  // a chunk at a time (spread_ahead), and what is left of it is spread when it comes up.
  static BucketCalendar spreading_ahead(double events_per_bucket = kPerBucket, double span = kSpan,
                                        int fine_per_coarse = kFinePerCoarse) {
    BucketCalendar c(events_per_bucket, span, fine_per_coarse);
    c.ahead_ = true;
    return c;
  }

  void reset(CalendarKeys key, const CellGrid* grid, int n_disks, int n_timers) {
    reset(key, grid, n_disks, n_timers, [](int) { return true; });
  }
  // The same with only the entries `keep` takes (a lane of the parallel loop: its band's).
  template <class Keep>
  void reset(CalendarKeys key, const CellGrid* grid, int n_disks, int n_timers, Keep&& keep) {
    key_ = key;
    grid_ = grid;
    nd_ = n_disks;
    ne_ = n_disks + n_timers;
    if (ne_ > kMaxEntries)
      throw Error("ed: bucket calendar: " + std::to_string(ne_) + " entries (disk slots and timers); at most " +
                  std::to_string(kMaxEntries) + " fit its 3-byte ids");
    f_ = std::min(max_f_, static_cast<std::int32_t>(std::bit_floor(static_cast<unsigned>(std::max(1, ne_ / 64)))));
    f_shift_ = std::countr_zero(static_cast<unsigned>(f_));
    ring_ = ahead_ ? 2 * f_ : f_;
    const std::int64_t want = std::max<std::int64_t>(64, static_cast<std::int64_t>(span_ * ne_ / per_bucket_));
    nc_ = static_cast<std::int32_t>((want + f_ - 1) / f_);
    nb_ = static_cast<std::int64_t>(nc_) * f_;
    heap_.clear();
    heap_.reserve(64);
    pool_.clear();
    free_ = -1;
    // The ring of fine buckets comes first, then the coarse ones, then the overflow.
    bucket_.assign(static_cast<std::size_t>(overflow_id()) + 1, Bucket{});
    n_copies_ = 0;
    std::vector<std::int32_t> all;
    for (int e = 0; e < ne_; ++e)
      if (std::isfinite(key_[e]) && keep(e)) all.push_back(e);
    lay_out(all);
  }

  // Entry e's key changed (to anything, infinity included): its new copy goes where the
  // key falls; the old one turns stale.
  void update(int e) { insert(e); }
  void moved(int, int, int) {}
  // Entry e's disk left the system (its key is already kNever, so its copies are stale).
  void removed(int, int) {}
  void commit() {}

  int top() {
    for (;;) {
      while (!heap_.empty() && stale(heap_[0])) heap_pop();
      if (!heap_.empty()) return heap_[0].e;
      if (n_copies_ == 0) return -1;
      ++cur_;
      const std::int64_t rel = cur_ - w0_;
      if (rel >= nb_) {
        rebuild();
        continue;
      }
      if (fine_of(rel) == 0) {
        if (!ahead_) knext_ = coarse_of(rel);  // not spread yet at all
        spread_rest();  // the coarse bucket coming up, spread ahead so far in part or not at all
        kcur_ = coarse_of(rel);
        begin_spread();
      }
      dump(ring_of(rel));
    }
  }

  // Spreading ahead, spreads one more chunk of the next coarse bucket, if any is left; false
  // when none is. A lane calls it while it waits on the other lane, so the spreading costs
  // it no time of its own. (Spreading a whole coarse bucket when it comes up, about a
  // thousand copies, takes tens of microseconds and holds up the other lane at its next
  // edge event; a chunk at each fine bucket avoids that but still takes the lane's time.)
  // When a copy is spread changes nothing in the order of events.
  bool spread_ahead() {
    if (knext_ < 0 || bucket_[static_cast<std::size_t>(coarse_id(knext_))].head < 0) return false;
    spread_next(1);
    return true;
  }

  // The key of the copy top() returned: what the calendar ordered it by. (A lane of the
  // parallel loop must not read the entry's record again: the other lane may have just
  // re-scheduled that disk, and a later key would claim events not yet processed.)
  double top_key() const { return heap_[0].key; }
  // Leaves out the copy top() returned (a lane's copy of an entry the other lane now owns).
  void drop_top() { heap_pop(); }
  double bucket_width() const { return dt_; }
  // The chunks counted are those ever handed out (the pool's high-water mark), not the
  // vector's capacity: its doubling reserve, up to as much again, is never touched.
  std::size_t memory_bytes() const {
    return heap_.capacity() * sizeof(HeapCopy) + pool_.size() * sizeof(Chunk) + bucket_.capacity() * sizeof(Bucket);
  }

private:
  // A heap copy carries the key it was pushed with, so sifting compares in place and a
  // copy is stale once the entry's key is another.
  struct HeapCopy {
    double key;
    std::int32_t e;
  };
  bool stale(const HeapCopy& c) const { return key_[c.e] != c.key; }
  static bool less(const HeapCopy& a, const HeapCopy& b) { return a.key < b.key || (a.key == b.key && a.e < b.e); }

  // Bucket ids: the ring of fine buckets, then the nc coarse ones, then the overflow.
  std::int32_t coarse_id(std::int32_t k) const { return ring_ + k; }
  std::int32_t overflow_id() const { return ring_ + nc_; }
  // Bucket rel ≥ 0 of the window: its coarse bucket, its place in it, and its fine bucket
  // in the ring (which holds the coarse bucket being processed and the next one).
  std::int32_t coarse_of(std::int64_t rel) const { return static_cast<std::int32_t>(rel >> f_shift_); }
  std::int32_t fine_of(std::int64_t rel) const { return static_cast<std::int32_t>(rel & (f_ - 1)); }
  std::int32_t ring_of(std::int64_t rel) const { return static_cast<std::int32_t>(rel & (ring_ - 1)); }

  // floor(t / dt) without the libm call std::floor compiles to on baseline x86-64, and with
  // a multiplication: any bucket map monotone in t gives the same event order (entries of
  // one bucket are ordered by the heap), so rounding in 1/dt changes nothing.
  std::int64_t bucket_of(double t) const {
    const double q = t * inv_dt_;
    const auto b = static_cast<std::int64_t>(q);
    return b - (q < static_cast<double>(b));
  }
  // Where a copy of key t belongs now: kHeap (the fine bucket being processed, or earlier),
  // its fine bucket in the ring (a key in the coarse bucket being processed, or in the next
  // one once its spreading has begun), its coarse bucket, the overflow, or kNowhere (an
  // infinite key).
  static constexpr std::int32_t kNowhere = -1;
  static constexpr std::int32_t kHeap = -2;
  std::int32_t place(double t) const {
    if (!std::isfinite(t)) return kNowhere;
    const std::int64_t b = bucket_of(t);
    if (b <= cur_) return kHeap;
    const std::int64_t rel = b - w0_;
    if (rel >= nb_) return overflow_id();
    const std::int32_t k = coarse_of(rel);
    return k == kcur_ || k == knext_ ? ring_of(rel) : coarse_id(k);
  }

  void insert(int e) {
    const double t = key_[e];
    const std::int32_t id = place(t);
    if (id == kHeap) heap_push({t, e});
    else if (id != kNowhere) list_push(id, e);
  }
  // Appends e to bucket `id` (a fine or coarse bucket, or the overflow).
  void list_push(std::int32_t id, int e) {
    Bucket& b = bucket_[static_cast<std::size_t>(id)];
    if (b.tail < 0 || b.n == kChunkIds) {
      const std::int32_t c = new_chunk();
      if (b.tail < 0) b.head = c; else pool_[static_cast<std::size_t>(b.tail)].next = c;
      b.tail = c;
      b.n = 0;
    }
    pool_[static_cast<std::size_t>(b.tail)].set(b.n++, e);
    ++n_copies_;
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
  // Calls f(e) for every id in the first max_chunks chunks of bucket `id` (stale copies
  // included), takes them out of it and returns them to the pool. Each chunk's keys (which
  // f reads: a miss each, at random) are prefetched together before f sees them.
  // hint_cells: also fetch each disk's cell entry (the bucket goes to the heap: its events
  // come next, and the loop starts each by reading the disk's cell).
  static constexpr int kAllChunks = std::numeric_limits<int>::max();
  template <bool hint_cells = false, class F>
  void drain(std::int32_t id, int max_chunks, F&& f) {
    const Bucket b = bucket_[static_cast<std::size_t>(id)];
    bucket_[static_cast<std::size_t>(id)] = Bucket{};
    std::int32_t c = b.head;
    for (int taken = 0; c >= 0 && taken < max_chunks; ++taken) {
      // By index, not by reference: f may append to other buckets and so grow the pool.
      const std::size_t ci = static_cast<std::size_t>(c);
      const std::int32_t next = pool_[ci].next;
      if (next >= 0) __builtin_prefetch(&pool_[static_cast<std::size_t>(next)]);
      const int n = c == b.tail ? b.n : kChunkIds;
      for (int q = 0; q < n; ++q) {
        const int e = pool_[ci].id(q);
        __builtin_prefetch(key_.at(e));
        if constexpr (hint_cells)
          if (grid_ && e < nd_) grid_->prefetch_cell(e);
      }
      n_copies_ -= n;
      for (int q = 0; q < n; ++q) f(pool_[ci].id(q));
      pool_[ci].next = free_;
      free_ = c;
      c = next;
    }
    if (c >= 0) {  // the chunks left stay the bucket's (f appended nothing to it)
      Bucket& rest = bucket_[static_cast<std::size_t>(id)];
      rest.head = c;
      rest.tail = b.tail;
      rest.n = b.n;
    }
  }

  // Spreading ahead (a lane), the next coarse bucket is spread into the ring (2F fine
  // buckets) while the current one is processed (spread_ahead). Once spreading may begin
  // (knext_), new copies of keys in that coarse bucket go straight to the ring, so its
  // coarse bucket only shrinks. A copy counts when its key falls in the coarse bucket being
  // spread (the window holds it). Not spreading ahead (one loop), knext_ names the coming
  // coarse bucket only while spread_rest spreads it whole.
  void begin_spread() {
    knext_ = ahead_ && kcur_ + 1 < nc_ ? kcur_ + 1 : -1;
  }
  // The rest of the coarse bucket coming up (the one being spread), at its first fine bucket.
  void spread_rest() {
    if (knext_ >= 0) spread_next(kAllChunks);
  }
  // The first max_chunks chunks of the coarse bucket being spread go to the ring.
  void spread_next(int max_chunks) {
    drain(coarse_id(knext_), max_chunks, [this](std::int32_t e) {
      const double t = key_[e];
      if (!std::isfinite(t)) return;
      const std::int64_t rel = bucket_of(t) - w0_;
      if (rel >= 0 && rel < nb_ && coarse_of(rel) == knext_) list_push(ring_of(rel), e);
    });
  }
  // Fine bucket s of the ring (the current one) comes up: its live copies go to the heap.
  void dump(std::int32_t s) {
    drain<true>(s, kAllChunks, [&](std::int32_t e) {
      const double t = key_[e];
      if (std::isfinite(t) && bucket_of(t) == cur_) heap_push({t, e});
    });
  }

  // Called when the window is used up (so every live copy sits in the overflow): re-tune
  // dt from the current spread of event times and lay out a new window.
  void rebuild() {
    // Nearly every entry is live here, so the live ones are marked in a bitmap (ne bits)
    // and read back in entry order: one id per entry, and the layout does not depend on
    // list history. (Sorting the ids took 2 % of the one loop's time at 1.6 × 10^5.)
    std::vector<std::uint64_t> mark(static_cast<std::size_t>(ne_ + 63) / 64, 0);
    const std::int32_t id = overflow_id();
    // cur_ has just passed the window, so place() would name the heap for keys in its
    // first bucket beyond: a copy counts when its key lies beyond the window.
    drain(id, kAllChunks, [&](std::int32_t e) {
      const double t = key_[e];
      if (std::isfinite(t) && bucket_of(t) - w0_ >= nb_)
        mark[static_cast<std::size_t>(e) / 64] |= std::uint64_t{1} << (e % 64);
    });
    std::vector<std::int32_t> live;
    for (std::size_t w = 0; w < mark.size(); ++w)
      for (std::uint64_t bits = mark[w]; bits != 0; bits &= bits - 1)
        live.push_back(static_cast<std::int32_t>(64 * w) + std::countr_zero(bits));
    lay_out(live);
  }
  // Tunes dt to the spread of the given entries' keys (all finite, sorted, distinct, and
  // in no bucket) and lays out a window from the least of them.
  void lay_out(const std::vector<std::int32_t>& entries) {
    heap_.clear();
    cur_ = w0_ = 0;
    kcur_ = 0;
    knext_ = -1;
    if (entries.empty()) return;
    double tmin = std::numeric_limits<double>::infinity();
    for (int e : entries) tmin = std::min(tmin, key_[e]);
    double mean = 0.0;
    for (int e : entries) mean += key_[e] - tmin;
    mean /= static_cast<double>(entries.size());
    // n entries each firing about once per `mean` give n/mean events per unit time.
    double dt = per_bucket_ * mean / static_cast<double>(entries.size());
    if (!(dt > 0.0) || !std::isfinite(dt)) dt = dt_ > 0.0 ? dt_ : 1.0;
    // Keep bucket indices well inside int64 and dt above the spacing of doubles near tmin.
    dt = std::max(dt, std::abs(tmin) * 1e-13 + 1e-300);
    dt_ = dt;
    inv_dt_ = 1.0 / dt;
    cur_ = bucket_of(tmin);
    w0_ = cur_;
    begin_spread();  // the first two coarse buckets go straight to the ring
    for (int e : entries) insert(e);
  }

  void heap_push(HeapCopy c) {
    heap_.push_back(c);
    std::size_t p = heap_.size() - 1;
    while (p > 0) {
      const std::size_t parent = (p - 1) / 2;
      if (!less(c, heap_[parent])) break;
      heap_[p] = heap_[parent];
      p = parent;
    }
    heap_[p] = c;
  }
  void heap_pop() {
    const HeapCopy c = heap_.back();
    heap_.pop_back();
    const std::size_t size = heap_.size();
    if (size == 0) return;
    std::size_t p = 0;
    for (;;) {
      std::size_t ch = 2 * p + 1;
      if (ch >= size) break;
      if (ch + 1 < size && less(heap_[ch + 1], heap_[ch])) ++ch;
      if (!less(heap_[ch], c)) break;
      heap_[p] = heap_[ch];
      p = ch;
    }
    heap_[p] = c;
  }

  double per_bucket_, span_;
  std::int32_t max_f_;     // fine buckets per coarse bucket, at most
  bool ahead_ = false;     // spreading_ahead
  std::int32_t f_ = 1;     // fine buckets per coarse bucket
  std::int32_t ring_ = 1;  // fine buckets in the ring: 2F spreading ahead, else F
  int f_shift_ = 0;        // log2 f_
  CalendarKeys key_;
  const CellGrid* grid_ = nullptr;  // for cache hints only
  int ne_ = 0, nd_ = 0;
  std::int32_t nc_ = 0, kcur_ = 0;  // coarse buckets in the window; the one being processed
  std::int32_t knext_ = -1;         // the next one, being spread into the ring (or none)
  std::int64_t nb_ = 0, cur_ = 0, w0_ = 0;
  std::int64_t n_copies_ = 0;  // ids in the buckets, stale ones included
  double dt_ = 0.0, inv_dt_ = 0.0;
  // A bucket is a chain of chunks, appended at the tail; empty chunks form the free list.
  // One cache line per chunk: 20 ids of 3 bytes (15 of 4), then the link, which is the
  // byte a 4-byte read of the last id takes beyond it. A bucket keeps the fill of its
  // tail chunk (the others are full), so an append writes only the tail chunk.
  static constexpr int kChunkIds = 20;
  struct alignas(64) Chunk {
    std::uint8_t ids[kChunkIds * kId24Bytes];
    std::int32_t next;
    int id(int q) const { return load_id24(ids + kId24Bytes * q); }
    void set(int q, int e) { store_id24(ids + kId24Bytes * q, e); }
  };
  static_assert(sizeof(Chunk) == 64);
  struct Bucket {
    std::int32_t head = -1, tail = -1, n = 0;
  };
  HugeVector<Chunk> pool_;
  std::int32_t free_ = -1;
  std::vector<Bucket> bucket_;
  std::vector<HeapCopy> heap_;
};

}  // namespace grainflow::ed
