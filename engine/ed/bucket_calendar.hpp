// Event calendar with one scheduled event per entry in a bucket queue (Paul 2007, "A
// complexity O(1) priority queue for event driven molecular dynamics simulations",
// J. Comput. Phys. 221, 615): a window of time buckets of width dt, unsorted doubly linked
// lists, an overflow list beyond the window, and a small binary heap as the sorted
// near-future window (the bucket being processed). Same interface as CellHeapCalendar.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "engine/ed/calendar_keys.hpp"
#include "engine/ed/cell_grid.hpp"
#include "engine/ed/huge_pages.hpp"

namespace grainflow::ed {

class BucketCalendar {
public:
  static constexpr const char* kName = "bucket";

  // Tuning: expected events per bucket, and window span in mean event intervals of an entry.
  explicit BucketCalendar(double events_per_bucket = 2.0, double span = 8.0)
      : per_bucket_(events_per_bucket), span_(span) {}

  void reset(CalendarKeys key, const CellGrid* /*grid*/, int n_disks, int n_timers) {
    key_ = key;
    ne_ = n_disks + n_timers;
    nb_ = std::max<std::int64_t>(64, static_cast<std::int64_t>(span_ * ne_ / per_bucket_));
    head_.assign(nb_ + 1, -1);  // the last list is the overflow
    link_.assign(ne_, Link{});
    heap_.clear();
    heap_.reserve(64);
    n_listed_ = 0;
    cur_ = 0;
    w0_ = 0;
    // Everything starts in the overflow; rebuild() tunes dt and distributes it.
    for (int e = 0; e < ne_; ++e)
      if (std::isfinite(key_[e])) push_list(e, nb_);
    rebuild();
  }

  void update(int e) {
    const double t = key_[e];
    if (link_[e].where == kInHeap && std::isfinite(t) && bucket_of(t) <= cur_) {
      // Stays in the near-future window: re-sift in place.
      const int p = link_[e].hpos;
      if (p > 0 && less(e, heap_[(p - 1) / 2])) sift_up(p); else sift_down(p);
      return;
    }
    detach(e);
    insert(e);
  }
  void moved(int, int, int) {}
  // Entry e's disk left the system (its key is already kNever).
  void removed(int e, int /*cell*/) { detach(e); }
  void commit() {}

  int top() {
    while (heap_.empty()) {
      if (n_listed_ == 0) return -1;
      ++cur_;
      if (cur_ - w0_ >= nb_) {
        rebuild();
      } else {
        const std::int64_t slot = cur_ - w0_;
        for (int e = head_[slot]; e >= 0;) {
          const int nx = link_[e].next;
          --n_listed_;
          heap_push(e);
          e = nx;
        }
        head_[slot] = -1;
      }
    }
    return heap_[0];
  }

  // Calls f(e) for the entries likely to come up after the current top (its heap children,
  // or the head of the next bucket), so the loop can prefetch their data one event ahead.
  template <class F>
  void peek_next(F&& f) const {
    const std::size_t h = heap_.size();
    if (h > 1) f(heap_[1]);
    if (h > 2) f(heap_[2]);
    if (h <= 2 && cur_ + 1 - w0_ < nb_) {
      const int e = head_[cur_ + 1 - w0_];
      if (e >= 0) {
        __builtin_prefetch(&link_[e]);
        __builtin_prefetch(key_.at(e));
        f(e);
      }
    }
  }

  // Calls f(e) for up to `max` entries of the bucket `k` places after the current one,
  // walking its list (cache hints for the loop's software pipeline; prefetches the list
  // links and keys on the way).
  template <class F>
  void peek_bucket(int k, int max, F&& f) const {
    const std::int64_t slot = cur_ + k - w0_;
    if (slot >= nb_) return;
    int e = head_[slot];
    for (int q = 0; e >= 0 && q < max; ++q) {
      __builtin_prefetch(&link_[e]);
      __builtin_prefetch(key_.at(e));
      f(e);
      if (q + 1 < max) e = link_[e].next;
    }
  }

  double bucket_width() const { return dt_; }
  std::size_t memory_bytes() const {
    return (head_.capacity() + heap_.capacity()) * 4 + link_.capacity() * sizeof(Link);
  }

private:
  static constexpr std::int32_t kParked = -1;  // infinite key: in no list
  static constexpr std::int32_t kInHeap = -2;

  // floor(t / dt) without the libm call std::floor compiles to on baseline x86-64, and with
  // a multiplication: any bucket map monotone in t gives the same event order (entries of
  // one bucket are ordered by the heap), so rounding in 1/dt changes nothing.
  std::int64_t bucket_of(double t) const {
    const double q = t * inv_dt_;
    const auto b = static_cast<std::int64_t>(q);
    return b - (q < static_cast<double>(b));
  }
  bool less(int a, int b) const { return key_[a] < key_[b] || (key_[a] == key_[b] && a < b); }

  void insert(int e) {
    const double t = key_[e];
    if (!std::isfinite(t)) { link_[e].where = kParked; return; }
    const std::int64_t b = bucket_of(t);
    if (b <= cur_) heap_push(e);
    else if (b - w0_ < nb_) push_list(e, b - w0_);
    else push_list(e, nb_);
  }
  void push_list(int e, std::int64_t list) {
    const int h = head_[list];
    link_[e].next = h;
    link_[e].prev = -1;
    if (h >= 0) link_[h].prev = e;
    head_[list] = e;
    link_[e].where = static_cast<std::int32_t>(list);
    ++n_listed_;
  }
  void detach(int e) {
    const std::int32_t w = link_[e].where;
    if (w == kParked) return;
    if (w == kInHeap) {
      const int p = link_[e].hpos;
      const int last = heap_.back();
      heap_.pop_back();
      link_[e].hpos = -1;
      if (last != e) {
        heap_[p] = last;
        link_[last].hpos = p;
        if (p > 0 && less(last, heap_[(p - 1) / 2])) sift_up(p); else sift_down(p);
      }
    } else {
      if (link_[e].prev >= 0) link_[link_[e].prev].next = link_[e].next; else head_[w] = link_[e].next;
      if (link_[e].next >= 0) link_[link_[e].next].prev = link_[e].prev;
      --n_listed_;
    }
    link_[e].where = kParked;
  }

  // Called when the window is used up (so every scheduled entry sits in the overflow):
  // re-tune dt from the current spread of event times and lay out a new window.
  void rebuild() {
    scratch_.clear();
    double tmin = std::numeric_limits<double>::infinity();
    for (int e = head_[nb_]; e >= 0; e = link_[e].next) {
      scratch_.push_back(e);
      tmin = std::min(tmin, key_[e]);
    }
    head_[nb_] = -1;
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
    for (int e : scratch_) {
      link_[e].where = kParked;
      insert(e);
    }
  }

  void heap_push(int e) {
    heap_.push_back(e);
    link_[e].where = kInHeap;
    sift_up(static_cast<int>(heap_.size()) - 1);
  }
  void sift_up(int p) {
    const int e = heap_[p];
    while (p > 0) {
      const int parent = (p - 1) / 2;
      if (!less(e, heap_[parent])) break;
      heap_[p] = heap_[parent];
      link_[heap_[p]].hpos = p;
      p = parent;
    }
    heap_[p] = e;
    link_[e].hpos = p;
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
      link_[heap_[p]].hpos = p;
      p = c;
    }
    heap_[p] = e;
    link_[e].hpos = p;
  }

  double per_bucket_, span_;
  CalendarKeys key_;
  int ne_ = 0;
  std::int64_t nb_ = 0, cur_ = 0, w0_ = 0, n_listed_ = 0;
  double dt_ = 0.0, inv_dt_ = 0.0;
  // An entry's list links, list (or kInHeap/kParked) and heap position side by side: an
  // update touches one cache line per entry instead of four.
  struct alignas(16) Link {
    std::int32_t next = -1, prev = -1, where = kParked, hpos = -1;
  };
  HugeVector<Link> link_;
  HugeVector<int> head_;
  std::vector<int> heap_, scratch_;
};

}  // namespace grainflow::ed
