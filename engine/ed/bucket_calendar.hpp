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

#include "engine/ed/cell_grid.hpp"

namespace grainflow::ed {

class BucketCalendar {
public:
  static constexpr const char* kName = "bucket";

  // Tuning: expected events per bucket, and window span in mean event intervals of an entry.
  explicit BucketCalendar(double events_per_bucket = 2.0, double span = 8.0)
      : per_bucket_(events_per_bucket), span_(span) {}

  void reset(const double* key, const CellGrid* /*grid*/, int n_disks, int n_timers) {
    key_ = key;
    ne_ = n_disks + n_timers;
    nb_ = std::max<std::int64_t>(64, static_cast<std::int64_t>(span_ * ne_ / per_bucket_));
    head_.assign(nb_ + 1, -1);  // the last list is the overflow
    next_.assign(ne_, -1);
    prev_.assign(ne_, -1);
    where_.assign(ne_, kParked);
    hpos_.assign(ne_, -1);
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
    if (where_[e] == kInHeap && std::isfinite(t) && bucket_of(t) <= cur_) {
      // Stays in the near-future window: re-sift in place.
      const int p = hpos_[e];
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
          const int nx = next_[e];
          --n_listed_;
          heap_push(e);
          e = nx;
        }
        head_[slot] = -1;
      }
    }
    return heap_[0];
  }

  double bucket_width() const { return dt_; }
  std::size_t memory_bytes() const {
    return (head_.capacity() + next_.capacity() + prev_.capacity() + where_.capacity() +
            hpos_.capacity() + heap_.capacity()) * 4;
  }

private:
  static constexpr std::int32_t kParked = -1;  // infinite key: in no list
  static constexpr std::int32_t kInHeap = -2;

  std::int64_t bucket_of(double t) const { return static_cast<std::int64_t>(std::floor(t / dt_)); }
  bool less(int a, int b) const { return key_[a] < key_[b] || (key_[a] == key_[b] && a < b); }

  void insert(int e) {
    const double t = key_[e];
    if (!std::isfinite(t)) { where_[e] = kParked; return; }
    const std::int64_t b = bucket_of(t);
    if (b <= cur_) heap_push(e);
    else if (b - w0_ < nb_) push_list(e, b - w0_);
    else push_list(e, nb_);
  }
  void push_list(int e, std::int64_t list) {
    const int h = head_[list];
    next_[e] = h;
    prev_[e] = -1;
    if (h >= 0) prev_[h] = e;
    head_[list] = e;
    where_[e] = static_cast<std::int32_t>(list);
    ++n_listed_;
  }
  void detach(int e) {
    const std::int32_t w = where_[e];
    if (w == kParked) return;
    if (w == kInHeap) {
      const int p = hpos_[e];
      const int last = heap_.back();
      heap_.pop_back();
      hpos_[e] = -1;
      if (last != e) {
        heap_[p] = last;
        hpos_[last] = p;
        if (p > 0 && less(last, heap_[(p - 1) / 2])) sift_up(p); else sift_down(p);
      }
    } else {
      if (prev_[e] >= 0) next_[prev_[e]] = next_[e]; else head_[w] = next_[e];
      if (next_[e] >= 0) prev_[next_[e]] = prev_[e];
      --n_listed_;
    }
    where_[e] = kParked;
  }

  // Called when the window is used up (so every scheduled entry sits in the overflow):
  // re-tune dt from the current spread of event times and lay out a new window.
  void rebuild() {
    scratch_.clear();
    double tmin = std::numeric_limits<double>::infinity();
    for (int e = head_[nb_]; e >= 0; e = next_[e]) {
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
    cur_ = bucket_of(tmin);
    w0_ = cur_;
    for (int e : scratch_) {
      where_[e] = kParked;
      insert(e);
    }
  }

  void heap_push(int e) {
    heap_.push_back(e);
    where_[e] = kInHeap;
    sift_up(static_cast<int>(heap_.size()) - 1);
  }
  void sift_up(int p) {
    const int e = heap_[p];
    while (p > 0) {
      const int parent = (p - 1) / 2;
      if (!less(e, heap_[parent])) break;
      heap_[p] = heap_[parent];
      hpos_[heap_[p]] = p;
      p = parent;
    }
    heap_[p] = e;
    hpos_[e] = p;
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
      hpos_[heap_[p]] = p;
      p = c;
    }
    heap_[p] = e;
    hpos_[e] = p;
  }

  double per_bucket_, span_;
  const double* key_ = nullptr;
  int ne_ = 0;
  std::int64_t nb_ = 0, cur_ = 0, w0_ = 0, n_listed_ = 0;
  double dt_ = 0.0;
  std::vector<int> head_, next_, prev_, hpos_, heap_, scratch_;
  std::vector<std::int32_t> where_;
};

}  // namespace grainflow::ed
