// What the two lanes of the parallel ED loop (ParallelLoop) share: which lane owns each
// row of cells and which rows lie near the other lane's, each lane's published next event,
// and a mailbox each way for disks whose calendar entry the other lane must take in.
//
// The box is cut into two bands of cell rows; a disk belongs to the lane of its cell's
// row, and that lane processes its events in the total order of (key, entry). An event of
// a disk in a row at most kEdgeRows from the other band ("an edge event") may read or
// write disks of the other band's first rows (its partner, a crossing into them, the
// partner's neighbourhood when it is predicted again); an event farther in reads and
// writes only its own band's rows from the third on. So the lanes run their inner events
// freely, and an edge event waits until the other lane has published a next event later in
// that order (it has done everything before, and will not start another edge event until
// this one is done): every pair of events that touch a common disk or cell is processed in
// the same order as by one loop, and so with the same bits, whatever the interleaving.
#pragma once
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <limits>
#include <vector>

namespace grainflow::ed {

// An event's place in the order both calendars pop in.
struct EventOrder {
  double key = std::numeric_limits<double>::infinity();
  int e = -1;
  bool operator<(const EventOrder& o) const { return key < o.key || (key == o.key && e < o.e); }
};

class LaneLink {
public:
  static constexpr int kLanes = 2;
  // Rows within this distance of the other band hold the disks whose events are edge events.
  static constexpr int kEdgeRows = 3;
  static constexpr int kMinRows = 4 * kEdgeRows + 4;  // each band's inner rows are not empty
  // Rows within this distance of the other band keep stamps (late events); a late event
  // that reads a row farther in counts as a violation.
  static constexpr int kStampRows = kEdgeRows + 3;

  // ny rows, the first half (rounded down) to lane 0; periodic_y: the last row meets the first;
  // n_cells cells in all.
  void configure(int ny, bool periodic_y, int n_cells) {
    cell_time_.assign(static_cast<std::size_t>(n_cells), -std::numeric_limits<double>::infinity());
    violated_.store(false, std::memory_order_relaxed);
    row_class_.assign(static_cast<std::size_t>(ny), 0);
    const int half = ny / 2;
    for (int r = 0; r < ny; ++r) {
      int d = r < half ? half - 1 - r : r - half;  // rows to the middle cut
      if (periodic_y) d = std::min(d, r < half ? r : ny - 1 - r);  // or to the wrapped one
      const std::uint8_t k = static_cast<std::uint8_t>((r < half ? 0 : kLaneOne) | (d < kEdgeRows ? kEdge : 0) |
                                                       (d <= kEdgeRows ? kPartnerMatters : 0) |
                                                       (d < kStampRows ? kStamped : 0) |
                                                       (d <= kStampRows ? kNearStamped : 0));
      row_class_[static_cast<std::size_t>(r)] = k;
    }
    for (auto& p : pub_) publish_raw(p, EventOrder{});
    for (auto& m : box_) {
      m.head.store(0, std::memory_order_relaxed);
      m.tail.store(0, std::memory_order_relaxed);
      m.read = 0;  // else a restart after mail would skip the first items sent
    }
  }
  int owner_of_row(int r) const { return row_class(r) & kLaneOne; }

  // ---- late events ----------------------------------------------------------------------
  // A lane runs its inner events without waiting, so an event the other lane mails it may
  // come due after later ones of its own. Those it did not touch are unaffected — but the
  // mailed event's consequences can reach them (a chain of collisions into the inner rows,
  // in no time at all in a dense cluster: hard disks give no look-ahead). So each cell keeps
  // the time of the last event that changed a member or the membership (stamp), and a lane
  // taking an event later than one it already did checks the cells the event reads: a
  // stamp at or after its time means the order of one loop may be broken (a violation).
  // The loop then does the run again from its start, in the merged order (ParallelLoop).
  // Only the rows within kStampRows of the other band keep stamps (the events there are a
  // few per cent of all); a late event reading a row farther in is a violation outright.
  void stamp(int c, double t) {
    double& s = cell_time_[static_cast<std::size_t>(c)];
    if (s < t) s = t;
  }
  double stamp_of(int c) const { return cell_time_[static_cast<std::size_t>(c)]; }
  void violate() { violated_.store(true, std::memory_order_release); }
  bool violated() const { return violated_.load(std::memory_order_acquire); }
  std::size_t bytes() const {
    return cell_time_.capacity() * sizeof(double) + row_class_.capacity() + sizeof(box_);
  }
  // Rows by their distance to the other band: edge rows, rows that keep stamps, and rows
  // next to those (an event there may change a cell of a stamped row: a partner, a crossing).
  bool edge_row(int r) const { return (row_class(r) & kEdge) != 0; }
  // The row next to the edge rows, and those: a pair event of a disk here may have its
  // partner in an edge row or in the other band (farther in, a partner in the 3×3 block
  // lies in this band's inner rows).
  bool partner_row(int r) const { return (row_class(r) & kPartnerMatters) != 0; }
  bool stamp_row(int r) const { return (row_class(r) & kStamped) != 0; }
  bool near_stamp_row(int r) const { return (row_class(r) & kNearStamped) != 0; }

  // ---- published next events ----------------------------------------------------------
  // Lane k is about to process (or is processing) o, and has processed everything before it.
  // Unchanged (a lane waiting on the other), nothing is written: a store would take the
  // line from the other lane's cache, which reads it while it waits in turn.
  void publish(int k, EventOrder o) {
    Published& p = pub_[k];
    if (p.key.load(std::memory_order_relaxed) == o.key && p.e.load(std::memory_order_relaxed) == o.e) return;
    publish_raw(p, o);
  }
  EventOrder published(int k) const {
    const Published& p = pub_[k];
    for (;;) {
      const std::uint64_t s0 = p.seq.load(std::memory_order_acquire);
      const double key = p.key.load(std::memory_order_relaxed);
      const int e = p.e.load(std::memory_order_relaxed);
      std::atomic_thread_fence(std::memory_order_acquire);
      if ((s0 & 1u) == 0 && p.seq.load(std::memory_order_relaxed) == s0) return {key, e};
    }
  }

  // ---- mailboxes: disks whose event the receiving lane must (re)schedule ----------------
  // Sent by the one other lane (single producer), taken by lane `to` (single consumer).
  void send(int to, int e, double key) {
    Mailbox& m = box_[to];
    const std::uint64_t h = m.head.load(std::memory_order_relaxed);
    // Only edge events send, and they never run at once, so the receiver drains while the
    // sender waits here.
    while (h - m.tail.load(std::memory_order_acquire) >= kMailbox) spin();
    m.item[h % kMailbox] = EventOrder{key, e};
    m.head.store(h + 1, std::memory_order_release);
  }
  // Calls f(e) for each disk sent to lane `to` since the last take; the caller then
  // publishes its next event and calls taken(to) (in that order: the sender's check reads
  // the taken mark, then the published event).
  template <class F>
  void take(int to, F&& f) {
    Mailbox& m = box_[to];
    const std::uint64_t h = m.head.load(std::memory_order_acquire);
    if (h == m.read) return;  // no store: the line is the sender's to read (tail)
    for (std::uint64_t k = m.read; k < h; ++k) f(m.item[k % kMailbox].e);
    m.read = h;
  }
  void taken(int to) {
    Mailbox& m = box_[to];
    if (m.tail.load(std::memory_order_relaxed) != m.read) m.tail.store(m.read, std::memory_order_release);
  }
  bool mail_waiting(int to) const {
    return box_[to].head.load(std::memory_order_acquire) != box_[to].read;
  }

  // May lane k process the edge event o? When the other lane has published a later event
  // and has taken in every disk k sent it that is due no later than o.
  bool other_is_past(int k, EventOrder o) const {
    const int other = 1 - k;
    const Mailbox& m = box_[other];
    const std::uint64_t tail = m.tail.load(std::memory_order_acquire);
    if (!(o < published(other))) return false;
    const std::uint64_t h = m.head.load(std::memory_order_relaxed);  // k's own sends
    for (std::uint64_t q = tail; q < h; ++q)
      if (!(o < m.item[q % kMailbox])) return false;
    return true;
  }
  // The other lane has no event up to t left and has taken in all that k sent it.
  bool other_done(int k, double t) const {
    const int other = 1 - k;
    const Mailbox& m = box_[other];
    if (m.tail.load(std::memory_order_acquire) != m.head.load(std::memory_order_relaxed)) return false;
    return published(other).key > t;
  }

  static void spin() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
  }

private:
  // What one lane writes while the other reads it sits alone on a 128-byte pair of cache
  // lines (the adjacent-line prefetcher moves lines in pairs): a line shared with what the
  // other lane writes would bounce between the cores at every event.
  static constexpr std::size_t kApart = 128;
  struct alignas(kApart) Published {
    std::atomic<std::uint64_t> seq{0};
    std::atomic<double> key{std::numeric_limits<double>::infinity()};
    std::atomic<int> e{-1};
  };
  static void publish_raw(Published& p, EventOrder o) {
    const std::uint64_t s = p.seq.load(std::memory_order_relaxed);
    p.seq.store(s + 1, std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_release);
    p.key.store(o.key, std::memory_order_relaxed);
    p.e.store(o.e, std::memory_order_relaxed);
    p.seq.store(s + 2, std::memory_order_release);
  }
  static constexpr std::uint64_t kMailbox = 4096;
  struct Mailbox {
    alignas(kApart) std::atomic<std::uint64_t> head{0};  // written by the sender
    alignas(kApart) std::atomic<std::uint64_t> tail{0};  // written by the receiver: taken up to here
    std::uint64_t read = 0;                              // the receiver's own: read up to here
    alignas(kApart) EventOrder item[kMailbox];
  };
  static constexpr std::uint8_t kLaneOne = 1, kEdge = 2, kStamped = 4, kNearStamped = 8, kPartnerMatters = 16;
  std::uint8_t row_class(int r) const { return row_class_[static_cast<std::size_t>(r)]; }
  std::vector<std::uint8_t> row_class_;  // owner and distance class of each row (configure)
  std::vector<double> cell_time_;  // stamps
  alignas(kApart) std::atomic<bool> violated_{false};
  Published pub_[kLanes];
  Mailbox box_[kLanes];
};

}  // namespace grainflow::ed
