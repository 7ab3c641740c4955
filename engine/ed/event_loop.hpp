// The event loop of the ED engine (seed 003 §2.1–2.5), templated on the calendar so the
// hot path has no virtual calls: disk–disk collisions and cell crossings are built in,
// every other agent comes in through ParticleAgent/TimerAgent. Stale events are recognised
// by the partner's event counter (DynamO style), so "affected" disks (§2.1) are re-predicted
// lazily, only when their own outdated event comes up. Inelastic runs may use the TC model
// of Luding & McNamara 1998 (seed 003 ch. 5, tc_verdict below); elastic ones never touch it.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <thread>
#include <vector>

#include "engine/ed/lane_link.hpp"
#include "engine/ed/scan_kernel.hpp"
#include "engine/ed/system_state.hpp"

namespace grainflow::ed {

// One performed disk–disk collision, for tests and tracing.
struct CollisionRecord {
  int i, j;
  double t;
};

class EventLoopBase {
public:
  virtual ~EventLoopBase() = default;
  // Predicts every disk and timer and fills the calendar (call after any bulk change).
  virtual void start() = 0;
  // Rebuilds the calendar from the event records as they stand, predicting nothing (after
  // SystemState::restore, a checkpoint): both calendars pop in the total order of
  // (key, entry index), which the records alone decide, so the restored run continues
  // bit for bit. Changes made from outside and saved unsettled are settled, as always,
  // when the next run starts.
  virtual void resume() = 0;
  // Processes every event with time ≤ t, then sets the clock to t.
  virtual void run_until(double t) = 0;
  // The same, but stops after `max_events` events (the clock then stays at the last
  // event's time): a caller that must stay responsive (Ctrl-C, a collapsing inelastic
  // system whose clock stops advancing) gets control back. True when t was reached.
  virtual bool run_until(double t, std::uint64_t max_events) = 0;
  // Processes n events (any kind; stale ones included) or fewer if nothing is scheduled.
  virtual std::uint64_t advance(std::uint64_t n) = 0;
  virtual double next_event_time() = 0;
  virtual std::size_t calendar_bytes() const = 0;
  virtual const char* calendar_name() const = 0;
  // The two-lane loop's runs between stops on two threads, and of them those it did again
  // in the merged order (ParallelLoop::run_lanes); zero for the one loop.
  struct LaneRuns {
    std::uint64_t runs = 0, redone = 0;
  };
  virtual LaneRuns lane_runs() const { return {}; }
  // Memory the two-lane loop keeps besides the state and its calendars: the copy a run is
  // done again from, and the stamps (both cold: written once a run, or near the cut only).
  virtual std::size_t lane_bytes() const { return 0; }
  std::function<void(const CollisionRecord&)> on_collision;  // empty: no tracing
};

// kLane: one of the two lanes of ParallelLoop (parallel_loop.hpp), which keeps its own
// clock and books (LaneBooks), takes only the events of its band of cell rows, and sends
// the disks of the other band whose events it changes to the other lane (LaneLink);
// ParallelLoop drives it through the lane_ functions below. Otherwise the one loop of a
// simulation, on the state's own clock and books.
template <class Calendar, bool kLane = false>
class EventLoop final : public EventLoopBase {
public:
  explicit EventLoop(SystemState& s, Calendar cal = Calendar()) : s_(s), cal_(std::move(cal)) {}

  void start() override {
    const int n = s_.size();
    const int nt = static_cast<int>(s_.timers.size());
    predict_all(nt);
    s_.clear_changes();
    s_.clear_touched();
    s_.clear_rescheduled();  // every timer is asked below
    for (int a = 0; a < nt; ++a) s_.event[n + a].key = std::max(now(), s_.timers[a]->event_time(s_));
    cal_.reset(s_.calendar_keys(), &s_.grid, n, nt);
  }

  void resume() override {
    cal_.reset(s_.calendar_keys(), &s_.grid, s_.size(), static_cast<int>(s_.timers.size()));
  }

  void run_until(double t) override {
    settle_outside_actions();
    for (;;) {
      const int e = cal_.top();
      if (e < 0 || s_.event[e].key > t) break;
      process(e);
    }
    advance_clock(t);
  }

  bool run_until(double t, std::uint64_t max_events) override {
    settle_outside_actions();
    for (std::uint64_t k = 0; k < max_events; ++k) {
      const int e = cal_.top();
      if (e < 0 || s_.event[e].key > t) {
        advance_clock(t);
        return true;
      }
      process(e);
    }
    return false;
  }

  std::uint64_t advance(std::uint64_t n) override {
    settle_outside_actions();
    std::uint64_t k = 0;
    for (; k < n; ++k) {
      const int e = cal_.top();
      if (e < 0) break;
      process(e);
    }
    return k;
  }

  double next_event_time() override {
    const int e = cal_.top();
    return e < 0 ? kNever : s_.event[e].key;
  }
  std::size_t calendar_bytes() const override { return cal_.memory_bytes(); }
  const char* calendar_name() const override { return Calendar::kName; }

  // ---- a lane of ParallelLoop (kLane only) ---------------------------------------------
  void lane_attach(LaneLink* link, int me) {
    static_assert(kLane);
    link_ = link;
    me_ = me;
  }
  LaneBooks& lane_books() { return books_; }
  // Fills the calendar with the events of the disks in this lane's band (the records as
  // they stand).
  void lane_fill() {
    mine_.assign(static_cast<std::size_t>(s_.size() + 63) / 64, 0);
    for (int i = 0; i < s_.size(); ++i) set_mine(i, s_.present(i) && owner(i) == me_);
    cal_.reset(s_.calendar_keys(), &s_.grid, s_.size(), 0, [this](int e) { return owns(e); });
  }
  // Predicts every disk present on this lane's clock, with unscheduled records for n_timers
  // timers (the records only; lane_fill then).
  void lane_predict_all(int n_timers) { predict_all(n_timers); }
  // Disk i predicted afresh on this lane's clock (the record only; lane_fill then).
  void lane_predict(int i) { predict_full(i); }
  // This lane's next event: the mail is taken in first, and copies of entries that now
  // belong to the other lane are dropped.
  EventOrder lane_next() {
    link_->take(me_, [this](int e) {
      set_mine(e, true);
      cal_.update(e);
    });
    for (;;) {
      const int e = cal_.top();
      if (e < 0) return EventOrder{};
      if (owns(e)) return EventOrder{cal_.top_key(), e};
      cal_.drop_top();
    }
  }
  // Processes e, the lane's next event, with no regard to the other lane (ParallelLoop's
  // merged order on one thread: every event is in the order of one loop).
  void lane_process(int e) {
    serial_ = true;
    process(e);
  }
  // Takes in the clock, and what the lanes read of the state as fixed while they run (the
  // TC model's state and cutoff, whether disks may be frozen), at the start of a run.
  void lane_start(double t) {
    books_.start(t);
    horizon_ = EventOrder{-std::numeric_limits<double>::infinity(), -1};
    deferred_ = -1;
    tc_on_ = s_.tc_on();
    tc_tau_ = s_.tc.tau;
    if (tc_on_) s_.tc_times();  // sized here, not by a lane
    maybe_frozen_ = s_.frozen_count() > 0 || !s_.agents.empty();
  }
  // Settles disks added or removed, or slots grown, by a timer at a stop, with the lanes at
  // rest: the records only (the caller then fills the calendars).
  void lane_settle() {
    resting_ = true;
    settle_changes();
    resting_ = false;
  }
  static constexpr std::size_t kLogCut = 1024, kLogMax = 1 << 16;  // events in the book log (lane_run)
  // Processes this lane's events up to time t (key ≤ t) while the other lane does its own
  // in another thread, and returns when both are done.
  void lane_run(double t) {
    LaneLink& l = *link_;
    // A lane that waits spreads its calendar ahead (BucketCalendar::spread_ahead) while
    // there is some to spread (8 % faster at 1.6 × 10^5 than a chunk at each fine bucket),
    // then spins, yielding the core now and then: with more threads than free cores the
    // lane being waited for must get to run.
    unsigned waits = 0;
    auto wait = [this, &waits] {
      if (cal_.spread_ahead()) return;
      if (++waits % 64 == 0) std::this_thread::yield();
      else LaneLink::spin();
    };
    books_.log = &book_log_;  // in the order of one loop (LaneBookLog)
    book_log_.settle(books_);
    for (;;) {
      if (l.violated()) break;  // the other lane found one: the run is done again anyway
      const EventOrder o = lane_next();
      l.publish(me_, o);
      l.taken(me_);
      // A long log (no edge event for a while: an empty edge zone) is cut where the other
      // lane is past all this lane did: no mail can then bring an event before it. One that
      // reaches kLogMax all the same has the run done again in the merged order (a lane
      // far ahead of the other: waiting here could wait on the other lane's edge event).
      if (book_log_.events() >= kLogCut && !(o < horizon_) &&
          (book_log_.events() % 64 == 0 || book_log_.events() >= kLogMax)) {
        if (!l.mail_waiting(me_) &&
            l.other_is_past(me_, EventOrder{horizon_.key, std::numeric_limits<int>::max()})) {
          book_log_.settle(books_);
        } else if (book_log_.events() >= kLogMax) {
          l.violate();
          break;
        }
      }
      if (!(o.key <= t)) {
        if (l.other_done(me_, t) && !l.mail_waiting(me_)) break;
        wait();
        continue;
      }
      serial_ = edge_event(o.e) || o.e == deferred_;
      if (serial_) {
        if (!l.other_is_past(me_, o)) {
          wait();
          continue;
        }
        // Mail the other lane sent before it moved on may hold an earlier event.
        if (l.mail_waiting(me_)) continue;
      }
      const bool late = o < horizon_;
      if (late && late_conflict(o)) {
        l.violate();
        break;
      }
      const Stamped cells = before_stamp(o.e);
      book_log_.begin_event(o.key, o.e);
      if (process(o.e)) {
        deferred_ = -1;
        if (late) book_log_.reorder_last(books_);
        else horizon_ = o;
        // Nothing can come before an edge event the other lane has passed: its sums are final.
        if (serial_ && !late) book_log_.settle(books_);
        after_stamp(o.e, cells, o.key);
      } else {
        deferred_ = o.e;  // found to need the other lane's order: done once it may
      }
    }
    books_.log = nullptr;
  }

private:
  using Candidate = ScanCandidate;

  // ---- late events (LaneLink::stamp) --------------------------------------------------
  // The cells event e changes a member of (or the membership of), as they are before it;
  // none when e's cell lies more than a row beyond the stamped rows (its partner's and a
  // crossing's new cell are then beyond them too).
  struct Stamped {
    int own = -1, partner = -1;
  };
  Stamped before_stamp(int e) const {
    Stamped c;
    const CellGrid& g = s_.grid;
    const int own = g.cell(e);
    if (!link_->near_stamp_row(g.iy(own))) return c;
    c.own = own;
    const NextEvent& ev = s_.event[e];
    if (!ev.crossing && ev.kind == EventKind::Pair) c.partner = g.cell(static_cast<int>(ev.partner));
    return c;
  }
  void after_stamp(int e, const Stamped& c, double t) {
    if (c.own < 0) return;
    stamp(c.own, t);
    if (s_.present(e)) stamp(s_.grid.cell(e), t);  // a crossing's new cell
    if (c.partner >= 0) stamp(c.partner, t);
  }
  void stamp(int c, double t) {
    if (link_->stamp_row(s_.grid.iy(c))) link_->stamp(c, t);
  }
  // Does event o, later than one this lane did, read a cell stamped at or after its time?
  // It reads the 3×3 blocks around its parties' cells (a crossing's new block lies in the
  // 5×5 around the old cell); an equal stamp may be a later entry's, so counts too.
  bool late_conflict(EventOrder o) const {
    const NextEvent& ev = s_.event[o.e];
    const int c = s_.grid.cell(o.e);
    if (stamped_after(c, ev.crossing ? 2 : 1, o.key)) return true;
    return !ev.crossing && ev.kind == EventKind::Pair &&
           stamped_after(s_.grid.cell(static_cast<int>(ev.partner)), 1, o.key);
  }
  bool stamped_after(int c, int reach, double t) const {
    const CellGrid& g = s_.grid;
    for (int ky = -reach; ky <= reach; ++ky) {
      int cy = g.iy(c) + ky;
      double sy = 0.0;
      if (!wrap(cy, g.ny(), g.periodic_y(), g.ly(), sy)) continue;
      if (!link_->stamp_row(cy)) return true;  // a row beyond the stamped ones
      for (int kx = -reach; kx <= reach; ++kx) {
        int cx = g.ix(c) + kx;
        double sx = 0.0;
        if (!wrap(cx, g.nx(), g.periodic_x(), g.lx(), sx)) continue;
        if (link_->stamp_of(g.index(cx, cy)) >= t) return true;
      }
    }
    return false;
  }

  // ---- the clock and the books: the state's own, or this lane's -----------------------
  double now() const {
    if constexpr (kLane) return books_.now;
    else return s_.now();
  }
  double since_epoch() const {
    if constexpr (kLane) return books_.now - s_.epoch();
    else return s_.since_epoch();
  }
  Stats& stats() {
    if constexpr (kLane) return books_.stats;
    else return s_.stats;
  }
  void advance_clock(double t) {
    if constexpr (kLane) books_.advance_clock(t);
    else s_.advance_clock(t);
  }
  void assign_velocity(int i, double vx, double vy) { s_.assign_velocity(i, vx, vy, since_epoch()); }
  void add_kinetic(double dk, double drot, double dpx, double dpy) {
    if constexpr (kLane) books_.add_kinetic(dk, drot, dpx, dpy);
    else s_.add_kinetic(dk, drot, dpx, dpy);
  }
  void add_kinetic_tensor(double m, double vx0, double vy0, double vx1, double vy1) {
    if constexpr (kLane) books_.add_kinetic_tensor(m, vx0, vy0, vx1, vy1);
    else s_.add_kinetic_tensor(m, vx0, vy0, vx1, vy1);
  }
  void add_virial(double rx, double ry, double jx, double jy) {
    if constexpr (kLane) books_.add_virial(rx, ry, jx, jy);
    else ed::add_virial(s_.stats, rx, ry, jx, jy);
  }
  // Entry e's event changed: into this loop's calendar, or (a lane, e in the other band)
  // into the other lane's mail.
  void reschedule(int e) {
    if constexpr (kLane) {
      if (resting_) return;
      const int to = owner(e);
      if (to != me_) {
        set_mine(e, false);  // a disk that crossed into the other band leaves
        link_->send(to, e, s_.event[e].key);
        return;
      }
    }
    cal_.update(e);
  }
  // A lane's disks are those it took in (its band's when it started, and the mail since):
  // its own record of them, since the other lane may be moving a disk it gave away.
  bool owns(int e) const { return (mine_[static_cast<std::size_t>(e) / 64] >> (e % 64)) & 1u; }
  void set_mine(int e, bool mine) {
    std::uint64_t& w = mine_[static_cast<std::size_t>(e) / 64];
    const std::uint64_t bit = std::uint64_t{1} << (e % 64);
    w = mine ? w | bit : w & ~bit;
  }
  int owner(int i) const { return link_->owner_of_row(s_.grid.iy(s_.grid.cell(i))); }
  bool edge_row_of(int i) const { return link_->edge_row(s_.grid.iy(s_.grid.cell(i))); }
  // Must this lane's event of disk i wait for the other lane? When i lies in an edge row,
  // or its record names a partner (a pair event, or one held behind a crossing) that is
  // not this lane's or lies in an edge row: everything such an event reads is then
  // written by the other lane only in its edge events, which wait in turn. (A partner of
  // this lane in an inner row is written by this lane alone; the other lane's disks in
  // its inner rows are never read: see far_partner.)
  // An agent's event is ordered with the other lane's the same way (it changes the agent's
  // state: its random stream, its counts, the disks it adds or takes out).
  // Farther in than the row next to the edge rows, a partner in i's 3×3 block lies in this
  // band's inner rows, and one beyond it is never read (far_partner): the partner's cell,
  // a cache miss at every event at 10^6 disks, is then not looked up. (Such a partner is
  // this lane's: a disk reaches these rows from the other band only by crossings of its
  // own, which are this lane's events once the mail bringing it is taken in.)
  bool edge_event(int i) const {
    const int r = s_.grid.iy(s_.grid.cell(i));
    if (link_->edge_row(r)) return true;
    const NextEvent& ev = s_.event[i];
    if (ev.kind == EventKind::Agent) return !ev.crossing;
    return ev.kind == EventKind::Pair && link_->partner_row(r) && (!owns(ev.partner) || edge_row_of(ev.partner));
  }
  // A lane does not read a partner outside the 3×3 cells around disk i: such a pair cannot
  // touch before one of them crosses a cell wall (cells are at least a diameter), so its
  // event is stale, and a crossing rescans i's neighbourhood instead of re-timing it. This
  // keeps the lane away from the other lane's inner rows, whose disks that lane may be
  // changing at the time (their cell, which is read here, may be changing too, but only
  // between rows that are all out of reach).
  bool far_partner(int i, int j) const {
    if constexpr (!kLane) return false;
    const CellGrid& g = s_.grid;
    const int ci = g.cell(i), cj = g.cell(j);
    int dx = std::abs(g.ix(ci) - g.ix(cj)), dy = std::abs(g.iy(ci) - g.iy(cj));
    if (g.periodic_x()) dx = std::min(dx, g.nx() - dx);
    if (g.periodic_y()) dy = std::min(dy, g.ny() - dy);
    return dx > 1 || dy > 1;
  }

  // False (nothing done) when a lane finds that the event must wait for the other lane's
  // order after all (an overlap removal in an event it took as inner: tc_verdict).
  bool process(int e) {
    ++stats().events;
    advance_clock(s_.event[e].key);
    if constexpr (!kLane) s_.maybe_rebase();  // the lanes' epoch moves only between their runs
    const int n = s_.size();
    // This event's own cells are fetched while its partner's counter is checked. (Hints for
    // the coming events, fetched in stages a few events ahead, were measured: with the
    // array-bucket calendar they cost 6 % in cache and gained nothing at 10^6 disks, where
    // the out-of-order core already overlaps the misses of consecutive events. With the
    // bucket calendar, the partner's record, counter and cell entry fetched for the heap's
    // next entry, or for each entry as its fine bucket goes to the heap, gained nothing
    // either at 1.4 × 10^6, in alternating windows of one run.)
    if (e < n) s_.grid.prefetch_block(s_.grid.cell(e));
    if (e >= n) {
      timer_event(e - n);
    } else if (s_.event[e].crossing) {
      // What a crossing reads once the disk has moved is fetched meanwhile: the held
      // partner's record, cell entry and counter (held_time, the staleness check), and the
      // row of cells the move brings into the disk's block (+3 % at 1.4 × 10^6).
      const NextEvent& ev = s_.event[e];
      if (ev.kind == EventKind::Pair) {
        prefetch_partner(ev.partner);
        __builtin_prefetch(&s_.counter[ev.partner]);
      }
      s_.grid.prefetch_beyond(s_.grid.cell(e), ev.cross_dir);
      crossing(e);
    } else if (s_.event[e].kind == EventKind::Pair) {
      const int j = s_.event[e].partner;
      // The partner's record and cell entry, which a collision reads first, are fetched
      // while its counter is checked.
      prefetch_partner(j);
      if (far_partner(e, j) || s_.counter[j] != s_.event[e].partner_count) {
        ++stats().stale;
        predict_full(e);
        reschedule(e);
      } else if (may_be_frozen() && (s_.frozen(e) || s_.frozen(j))) {
        if (!collide_frozen(e, j)) return undo_event();
      } else {
        if (!collide(e, j)) return undo_event();
      }
    } else {
      agent_event(e, s_.event[e].partner);
    }
    cal_.commit();
    return true;
  }
  // Cache hints (no effect on results): partner j's record and cell entry.
  void prefetch_partner(int j) const {
    __builtin_prefetch(&s_.disk[j]);
    s_.grid.prefetch_cell(j);
  }
  bool undo_event() {
    --stats().events;
    return false;
  }
  // The lanes take whether disks may be frozen at their start (the count changes as agents
  // freeze disks in the other lane).
  bool may_be_frozen() const {
    if constexpr (kLane) return maybe_frozen_;
    else return s_.frozen_count() > 0;
  }
  bool tc_on() const {
    if constexpr (kLane) return tc_on_;
    else return s_.tc_on();
  }
  // The TC cutoff: a lane's is the state's when it started (a removal raises the state's
  // at once; the lanes take it in at their next start, the same for one thread or two).
  double tc_tau() const {
    if constexpr (kLane) return tc_tau_;
    else return s_.tc.tau;
  }

  bool collide(int i, int j) {
    list_parties(i, j);
    const Disk& a = s_.disk[i];
    const Disk& b = s_.disk[j];
    double rx, ry;
    separation_now(i, j, rx, ry);
    // Smooth disks of one radius and one mass (the usual case) need nothing from the
    // bodies: no spin changes, and radius and mass are the common ones.
    const bool plain = s_.plain_disks();
    const double um = s_.uniform_mass();
    const double m1 = plain ? um : s_.body[i].m, m2 = plain ? um : s_.body[j].m;
    const double r1 = s_.radius(i), r2 = s_.radius(j);
    const double w1 = plain ? 0.0 : s_.body[i].w, w2 = plain ? 0.0 : s_.body[j].w;
    // TC model (inelastic runs with a cutoff only; elastic ones never enter).
    const CollisionParams* rule = &s_.rule;
    if (tc_on()) [[unlikely]] {
      const TcVerdict v = tc_verdict(i, j, rx * rx + ry * ry, r1 + r2, false);
      if (v == TcVerdict::deferred) return false;
      if (v == TcVerdict::removed) return true;
      if (v == TcVerdict::elastic) rule = &tc_elastic_rule();
    }
    const CollisionImpulse J = collision_impulse(rx, ry, a.vx - b.vx, a.vy - b.vy, r1, r2, w1, w2, m1, m2, *rule);
    const double avx = a.vx, avy = a.vy, bvx = b.vx, bvy = b.vy;  // before, for the books
    const double k0 = 0.5 * (m1 * (avx * avx + avy * avy) + m2 * (bvx * bvx + bvy * bvy));
    assign_velocity(i, avx + J.jx / m1, avy + J.jy / m1);
    assign_velocity(j, bvx - J.jx / m2, bvy - J.jy / m2);
    const double k1 = 0.5 * (m1 * (a.vx * a.vx + a.vy * a.vy) + m2 * (b.vx * b.vx + b.vy * b.vy));
    double drot = 0.0;
    if (J.dw1 != 0.0 || J.dw2 != 0.0) {  // rough disks only: plain is false
      DiskBody& ba = s_.body[i];
      DiskBody& bb = s_.body[j];
      ba.w += J.dw1;
      bb.w += J.dw2;
      drot = 0.5 * (s_.inertia(i) * (ba.w * ba.w - w1 * w1) +
                    s_.inertia(j) * (bb.w * bb.w - w2 * w2));
    }
    add_kinetic(k1 - k0, drot, 0.0, 0.0);
    add_kinetic_tensor(m1, avx, avy, a.vx, a.vy);
    add_kinetic_tensor(m2, bvx, bvy, b.vx, b.vy);
    add_virial(rx, ry, J.jx, J.jy);
    ++stats().collisions;
    if (J.sliding) ++stats().sliding;
    ++s_.counter[i];
    ++s_.counter[j];
    if (on_collision) on_collision(CollisionRecord{i, j, now()});
    // A heap-based calendar must see each key change before the next one (an entry whose
    // key changed but is not yet re-sifted would mislead the other's sift).
    predict_parties(i, j);
    return true;
  }

  void crossing(int i) {
    ++stats().cell_crossings;
    CellGrid& g = s_.grid;
    Disk& d = s_.disk[i];
    const int from = g.cell(i);
    int ix = g.ix(from), iy = g.iy(from);
    const int dir = s_.event[i].cross_dir;
    switch (dir) {
      case 0: if (++ix == g.nx()) { ix = 0; d.x -= g.lx(); } break;
      case 1: if (--ix < 0) { ix = g.nx() - 1; d.x += g.lx(); } break;
      case 2: if (++iy == g.ny()) { iy = 0; d.y -= g.ly(); } break;
      default: if (--iy < 0) { iy = g.ny() - 1; d.y += g.ly(); } break;
    }
    const int to = g.index(ix, iy);
    g.remove(i);
    g.insert(i, to);
    cal_.moved(i, from, to);
    const NextEvent& ev = s_.event[i];
    if (ev.kind == EventKind::Pair && (far_partner(i, ev.partner) || s_.counter[ev.partner] != ev.partner_count)) {
      predict_full(i);  // the remembered partner changed: the old neighbourhood must be rescanned
    } else {
      // The best event in the old neighbourhood still holds; only the newly adjacent row of
      // cells and the agents of the new cell can offer an earlier one (cells ≥ σ, §2.2).
      // Its time is not in the record (NextEvent): held_time finds it.
      const Disk di = now_record(i);
      const double ri = s_.radius(i);
      int who = ev.partner;
      EventKind kind = ev.kind;
      double best = held_time(i, di, ri, to, who, kind);
      int cells[3] = {};
      double shx[3] = {}, shy[3] = {};
      int nc = 0;
      if (dir < 2) {
        int cx = ix + (dir == 0 ? 1 : -1);
        double sx = 0.0;
        if (wrap(cx, g.nx(), g.periodic_x(), g.lx(), sx))
          for (int k = -1; k <= 1; ++k) {
            int cy = iy + k;
            double sy = 0.0;
            if (wrap(cy, g.ny(), g.periodic_y(), g.ly(), sy)) {
              cells[nc] = g.index(cx, cy);
              shx[nc] = sx;
              shy[nc++] = sy;
            }
          }
      } else {
        int cy = iy + (dir == 2 ? 1 : -1);
        double sy = 0.0;
        if (wrap(cy, g.ny(), g.periodic_y(), g.ly(), sy))
          for (int k = -1; k <= 1; ++k) {
            int cx = ix + k;
            double sx = 0.0;
            if (wrap(cx, g.nx(), g.periodic_x(), g.lx(), sx)) {
              cells[nc] = g.index(cx, cy);
              shx[nc] = sx;
              shy[nc++] = sy;
            }
          }
      }
      scan_cells(i, di, ri, cells, shx, shy, nc, best, who, kind);
      scan_agents(i, to, best, who, kind);
      schedule(i, best, who, kind);
    }
    reschedule(i);
  }

  // The time from now to disk i's held pair or agent event (`kind` with `who`; disk i at
  // di now, radius ri, in cell c), or kNever (then kind becomes None). A pair's is computed
  // again from the two records (a grazing pair that round-off now finds to miss is a miss);
  // an agent's was kept (SystemState::agent_time).
  double held_time(int i, const Disk& di, double ri, int c, int& who, EventKind& kind) const {
    if (kind == EventKind::Agent) return s_.agent_time[i] - now();
    if (kind != EventKind::Pair) return kNever;
    const Candidate partner[1 + kScanPad] = {{who, 0}, {i, 0}, {i, 0}, {i, 0}};
    double shx, shy;
    s_.grid.image_shift(c, s_.grid.cell(who), shx, shy);
    double best = kNever;
    int found = -1;
    EventKind what = EventKind::None;
    evaluate(di, ri, partner, 1, &shx, &shy, shx != 0.0 || shy != 0.0, best, found, what);
    kind = what;
    return best;
  }

  void agent_event(int i, int a) {
    ++stats().agent_events;
    ParticleAgent& agent = *s_.agents[a];
    if constexpr (kLane) s_.act_for_lane(books_, [&] { agent.action(s_, i); });
    else agent.action(s_, i);
    settle_changes();
    if (s_.present(i)) {  // the action may have removed it (outlet)
      predict_full(i);
      reschedule(i);
    }
    repredict_touched(i);
    // A lane leaves the timers it switched to the next stop (ParallelLoop::settle).
    if constexpr (!kLane) reschedule_timers();
  }

  void timer_event(int a) {
    ++stats().timer_events;
    TimerAgent& ag = *s_.timers[a];
    ag.action(s_);
    settle_changes();
    const int e = s_.size() + a;  // after settle_changes: the slots may have grown
    s_.event[e].key = std::max(now(), ag.event_time(s_));
    cal_.update(e);
    repredict_touched(-1);
    reschedule_timers();
  }

  // Timers another agent switched (SystemState::reschedule) are asked for their time again.
  void reschedule_timers() {
    if (s_.rescheduled().empty()) [[likely]] return;
    for (int b : s_.rescheduled()) {
      const int e = s_.size() + b;
      s_.event[e].key = std::max(now(), s_.timers[b]->event_time(s_));
      cal_.update(e);
    }
    s_.clear_rescheduled();
  }

  void repredict_touched(int skip) {
    for (int j : s_.touched())
      if (j != skip && s_.present(j)) {
        predict_full(j);
        reschedule(j);
      }
    s_.clear_touched();
  }

  // Disks added, removed, frozen or re-velocitied between runs (not by an agent's action).
  void settle_outside_actions() {
    if (s_.grown() || !s_.added().empty() || !s_.removed().empty() || !s_.touched().empty() ||
        !s_.rescheduled().empty()) {
      settle_changes();
      repredict_touched(-1);
      reschedule_timers();
      cal_.commit();
    }
  }

  // Disks that entered or left during an action (open stream boundaries, seed 003 §3.2–3.3).
  // Removed disks carry a bumped counter, so partners' events with them turn stale; added
  // ones are predicted, and so is every disk of the 3×3 cells around them, whose events
  // did not know the newcomer.
  void settle_changes() {
    // (Slots grow only when a timer adds disks; the lanes' timers act at stops, whose
    // caller refills the lanes' calendars.)
    if constexpr (!kLane)
      if (s_.grown()) cal_.reset(s_.calendar_keys(), &s_.grid, s_.size(), static_cast<int>(s_.timers.size()));
    for (const SystemState::Removal& r : s_.removed()) cal_.removed(r.id, r.cell);
    if (!s_.added().empty()) {
      around_.clear();
      const CellGrid& g = s_.grid;
      for (int i : s_.added()) {
        if (!s_.present(i)) continue;
        const int c = g.cell(i);
        for (int ky = -1; ky <= 1; ++ky) {
          int cy = g.iy(c) + ky;
          double sy = 0.0;
          if (!wrap(cy, g.ny(), g.periodic_y(), g.ly(), sy)) continue;
          for (int kx = -1; kx <= 1; ++kx) {
            int cx = g.ix(c) + kx;
            double sx = 0.0;
            if (!wrap(cx, g.nx(), g.periodic_x(), g.lx(), sx)) continue;
            const int cc = g.index(cx, cy);
            for (int k = 0; k < g.count(cc); ++k) around_.push_back(g.member(cc, k));
          }
        }
      }
      std::sort(around_.begin(), around_.end());
      around_.erase(std::unique(around_.begin(), around_.end()), around_.end());
      for (int j : around_) {
        predict_full(j);
        reschedule(j);
      }
    }
    s_.clear_changes();
  }

  // A disk meets a frozen (infinitely heavy) one: it reflects in the frozen disk's frame;
  // the frozen disk keeps its velocity and stays outside the books (Fig. 3.8).
  bool collide_frozen(int i, int j) {
    if (s_.frozen(i)) std::swap(i, j);  // i: the mobile disk (if any)
    const Disk& a = s_.disk[i];
    const Disk& b = s_.disk[j];
    DiskBody& ba = s_.body[i];
    const DiskBody& bb = s_.body[j];
    double rx, ry;
    separation_now(i, j, rx, ry);
    if (!s_.frozen(i)) {
      const double m = ba.m;
      const CollisionParams* rule = &s_.rule;
      if (tc_on()) [[unlikely]] {  // the mobile disk's clock alone: a frozen disk is a wall
        const TcVerdict v = tc_verdict(i, j, rx * rx + ry * ry, ba.r + bb.r, true);
        if (v == TcVerdict::deferred) return false;
        if (v == TcVerdict::removed) return true;
        if (v == TcVerdict::elastic) rule = &tc_elastic_rule();
      }
      const CollisionImpulse J = collision_impulse_heavy(rx, ry, a.vx - b.vx, a.vy - b.vy, ba.r, bb.r, ba.w,
                                                         bb.w, m, *rule);
      const double avx = a.vx, avy = a.vy;  // before, for the books
      const double k0 = 0.5 * m * (avx * avx + avy * avy);
      assign_velocity(i, avx + J.jx / m, avy + J.jy / m);
      const double k1 = 0.5 * m * (a.vx * a.vx + a.vy * a.vy);
      double drot = 0.0;
      if (J.dw1 != 0.0) {
        const double w1 = ba.w;
        ba.w += J.dw1;
        drot = 0.5 * s_.inertia(i) * (ba.w * ba.w - w1 * w1);
      }
      add_kinetic(k1 - k0, drot, J.jx, J.jy);  // the frozen disk absorbs −J
      add_kinetic_tensor(m, avx, avy, a.vx, a.vy);
      add_virial(rx, ry, J.jx, J.jy);
      ++stats().collisions;
      if (J.sliding) ++stats().sliding;
      ++s_.counter[i];
      if (on_collision) on_collision(CollisionRecord{i, j, now()});
    } else {
      // Two frozen disks only meet when agents froze them at different velocities: equal
      // (infinite) masses, smooth, elastic; outside the books.
      const CollisionImpulse J = collision_impulse(rx, ry, a.vx - b.vx, a.vy - b.vy, ba.r, bb.r, 0.0, 0.0, 1.0, 1.0,
                                                   CollisionParams{});
      assign_velocity(i, a.vx + J.jx, a.vy + J.jy);
      assign_velocity(j, b.vx - J.jx, b.vy - J.jy);
      ++stats().collisions;
      ++s_.counter[i];
      ++s_.counter[j];
      if (on_collision) on_collision(CollisionRecord{i, j, now()});
    }
    // j keeps its trajectory; its own event may have named i, so it is predicted again too.
    predict_full(i);
    reschedule(i);
    predict_full(j);
    reschedule(j);
    return true;
  }

  // ---- TC model (Luding & McNamara 1998; seed 003 ch. 5) --------------------------------
  enum class TcVerdict { inelastic, elastic, removed, deferred };

  // Decides a collision of i and j (r2: their squared distance now, at
  // contact, sigma: the sum of radii) with the TC model on. dt: the time since the more
  // recent of the two parties' previous disk–disk collisions (with j frozen, a wall:
  // i's alone).
  // * elastic (normal restitution 1) when dt < τ_TC, inelastic otherwise; both parties'
  //   times become now;
  // * but a numerical overlap — the centres closer than σ(1 − kOverlapGap) (or not
  //   finite), or an inelastic collision whose dt is below the clock's resolution (4 ulp
  //   of now: the collision time scale fell below the precision, seed 003 ch. 5; the
  //   stalled clock of a collapse) — removes the offending disk instead (the party whose
  //   previous collision is the more recent, the higher id on a tie; with j frozen, i),
  //   raises τ_TC by its step and predicts the other disk afresh: `removed`, nothing else
  //   happens. A lane does this only in the order of one loop (as an edge event: the
  //   removal changes the state's counts and free slots); found in an event it took as
  //   inner, the verdict is `deferred`, nothing has changed yet, and the lane does the
  //   event again once the other lane is past it.
  TcVerdict tc_verdict(int i, int j, double r2, double sigma, bool j_frozen) {
    std::vector<double>& last = s_.tc_times();
    const double now = this->now();
    const double ti = last[i], tj = j_frozen ? -kNever : last[j];
    const double dt = now - std::max(ti, tj);
    const bool elastic = dt < tc_tau();
    const double resolution = 4.0 * std::numeric_limits<double>::epsilon() * std::abs(now);
    const double c = r2 - sigma * sigma;
    if (!(c >= -2.0 * kOverlapGap * sigma * sigma) || (!elastic && dt <= resolution)) [[unlikely]] {
      if (!serial_) return TcVerdict::deferred;
      const int k = j_frozen ? i : ti > tj ? i : tj > ti ? j : std::max(i, j);
      const int other = k == i ? j : i;
      if constexpr (kLane) s_.act_for_lane(books_, [&] { s_.remove_overlapping(k); });
      else s_.remove_overlapping(k);
      settle_changes();  // takes k out of the calendar
      predict_full(other);
      reschedule(other);
      return TcVerdict::removed;
    }
    last[i] = now;
    if (!j_frozen) last[j] = now;
    return elastic ? TcVerdict::elastic : TcVerdict::inelastic;
  }

  // The rule of a TC-elastic collision: the configured one with normal restitution 1 (the
  // tangential part, e_t and μ, as configured); counted in stats.tc_elastic.
  const CollisionParams& tc_elastic_rule() {
    ++stats().tc_elastic;
    tc_rule_ = s_.rule;
    tc_rule_.e = 1.0;
    return tc_rule_;
  }

  // Steps a neighbour cell index across the grid edge; false when there is no such cell.
  static bool wrap(int& c, int n, bool periodic, double l, double& shift) {
    if (c < 0) {
      if (!periodic) return false;
      c += n;
      shift = -l;
    } else if (c >= n) {
      if (!periodic) return false;
      c -= n;
      shift = l;
    }
    return true;
  }

  // Earliest pair event of disk i with the disks of cells[0..nc) (image shifts shx, shy),
  // in two passes: first gather every candidate and prefetch its disk, so that all the
  // cache misses of the neighbourhood are in flight together (at large N the scan waits on
  // memory, not arithmetic), then compute branch-free. Candidates are visited in the
  // cells' order, so ties resolve as in a plain cell-by-cell scan.
  // di: disk i's position now (not at the epoch) and velocity; ri: its radius.
  void scan_cells(int i, const Disk& di, double ri, const int* cells, const double* shx, const double* shy, int nc,
                  double& best_out, int& who_out, EventKind& kind_out) {
    const int n = gather(i, cells, nc, cand_);
    bool shifted = false;
    for (int k = 0; k < nc; ++k) shifted |= shx[k] != 0.0 || shy[k] != 0.0;
    evaluate(di, ri, cand_.data(), n, shx, shy, shifted, best_out, who_out, kind_out);
  }
  // The first half of a scan: disk i's candidates from cells[0..nc) into buf, each one's
  // record fetched as it is listed, then the padding (kScanPad); returns their number.
  int gather(int i, const int* cells, int nc, std::vector<Candidate>& buf) {
    const CellGrid& g = s_.grid;
    const std::size_t need = static_cast<std::size_t>(nc) * static_cast<std::size_t>(g.capacity()) + kScanPad;
    if (buf.size() < need) buf.resize(need);
    // Local pointers: stores into the candidate list cannot alias them, so the loops
    // below do not reload the grid's fields at every step.
    CellGrid::Slots slot[9];
    for (int k = 0; k < nc; ++k) {
      slot[k] = g.cell_slots(cells[k]);
      __builtin_prefetch(slot[k].address());
    }
    const Disk* __restrict disk = s_.disk.data();
    const std::uint32_t* __restrict counter = s_.counter.data();
    Candidate* __restrict out = buf.data();
    Candidate* const first = out;
    for (int k = 0; k < nc; ++k) {
      const CellGrid::Slots s = slot[k];
      for (int q = 0, end = s.count(); q < end; ++q) {
        const int j = s.member(q);
        __builtin_prefetch(disk + j);
        __builtin_prefetch(counter + j);  // schedule reads the winner's
        *out = Candidate{j, k};
        out += (j != i);
      }
    }
    for (int p = 0; p < kScanPad; ++p) out[p] = Candidate{i, 0};
    return static_cast<int>(out - first);
  }
  // The second half: the earliest pair event of a disk at di now (radius ri) with the
  // candidates cand[0..n) (their cells' image shifts in shx, shy, read only when
  // `shifted`, else all taken as zero; the padding follows), if earlier than best_out.
  void evaluate(const Disk& di, double ri, const Candidate* __restrict cand, int n, const double* shx,
                const double* shy, bool shifted, double& best_out, int& who_out,
                EventKind& kind_out) const {
    // Each candidate is taken to now from the common epoch; with disks of one size the
    // sum of radii is a constant and the bodies are not read.
    const Disk* __restrict disk = s_.disk.data();
    const DiskBody* __restrict body = s_.body.data();
    const double since = since_epoch();
    const double ur = s_.uniform_radius();
    const bool mixed = !(ur > 0.0);
#if defined(GRAINFLOW_ED_AVX2)
    // Four candidates per step where the CPU has AVX2 (the same bits: scan_kernel.hpp).
    if (scan_uses_avx2()) {
      const double held = best_out;
      earliest_pair_avx2(ScanQuery{disk, body, shx, shy, di, ri, ur, since, mixed, shifted}, cand, n, best_out,
                         who_out);
      if (best_out < held) kind_out = EventKind::Pair;
      return;
    }
#endif
    if (!shifted) shx = shy = kNoShift;
    // Locals, so that the running minimum stays in registers (the references could alias
    // the stores below).
    double best = best_out;
    int who = who_out;
    EventKind kind = kind_out;
    int k = 0;
    // Two candidates per step in SSE2 lanes (the same IEEE operations in the same order
    // as pair_collision_time, so the same bits); the minimum is then taken in candidate order.
#if defined(__SSE2__)
    const __m128d dt = _mm_set1_pd(since), zero = _mm_setzero_pd(), never = _mm_set1_pd(kNever);
    const __m128d sign = _mm_set1_pd(-0.0);
    const __m128d vlimit = _mm_set1_pd(2.0 * (1.0 + 1e-12));
    const __m128d ix = _mm_set1_pd(di.x), iy = _mm_set1_pd(di.y), ivx = _mm_set1_pd(di.vx),
                  ivy = _mm_set1_pd(di.vy), ir = _mm_set1_pd(ri), usigma = _mm_set1_pd(ri + ur);
    for (; k + 1 < n; k += 2) {
      const Disk& p = disk[cand[k].j];
      const Disk& q = disk[cand[k + 1].j];
      const __m128d vx = _mm_set_pd(q.vx, p.vx), vy = _mm_set_pd(q.vy, p.vy);
      const __m128d jx = _mm_add_pd(_mm_add_pd(_mm_set_pd(q.x, p.x), _mm_mul_pd(vx, dt)),
                                    _mm_set_pd(shx[cand[k + 1].k], shx[cand[k].k]));
      const __m128d jy = _mm_add_pd(_mm_add_pd(_mm_set_pd(q.y, p.y), _mm_mul_pd(vy, dt)),
                                    _mm_set_pd(shy[cand[k + 1].k], shy[cand[k].k]));
      const __m128d dx = _mm_sub_pd(ix, jx), dy = _mm_sub_pd(iy, jy);
      const __m128d dvx = _mm_sub_pd(ivx, vx), dvy = _mm_sub_pd(ivy, vy);
      const __m128d sigma =
          mixed ? _mm_add_pd(ir, _mm_set_pd(body[cand[k + 1].j].r, body[cand[k].j].r)) : usigma;
      const __m128d b = _mm_add_pd(_mm_mul_pd(dx, dvx), _mm_mul_pd(dy, dvy));
      const __m128d v2 = _mm_add_pd(_mm_mul_pd(dvx, dvx), _mm_mul_pd(dvy, dvy));
      const __m128d c = _mm_sub_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)), _mm_mul_pd(sigma, sigma));
      const __m128d disc = _mm_sub_pd(_mm_mul_pd(b, b), _mm_mul_pd(v2, c));
      const __m128d ok = _mm_and_pd(_mm_cmplt_pd(b, zero), _mm_cmpge_pd(disc, zero));
      // Neither lane can beat `best`: skip the division and the square root, the scan's
      // longest dependency chain. With c ≥ 0, √D ≤ |b|, so t = c/(|b| + √D) ≥ c/(2|b|);
      // a lane is left out only when c ≥ 2|b| best (1 + 1e-12), which leaves a margin far
      // above the few ulp of rounding in t: the skipped lanes' t would not have been
      // taken, and the result is the same, bit for bit, as without the test.
      const __m128d reach = _mm_mul_pd(_mm_mul_pd(_mm_andnot_pd(sign, b), vlimit), _mm_set1_pd(best));
      if (_mm_movemask_pd(_mm_and_pd(ok, _mm_cmplt_pd(c, reach))) == 0) continue;
      const __m128d root = _mm_div_pd(c, _mm_add_pd(_mm_xor_pd(b, sign), _mm_sqrt_pd(disc)));
      const __m128d t = _mm_andnot_pd(_mm_cmple_pd(c, zero), root);  // contact now: +0
      alignas(16) double tt[2];
      _mm_store_pd(tt, _mm_or_pd(_mm_and_pd(ok, t), _mm_andnot_pd(ok, never)));
      if (tt[0] < best) {
        best = tt[0];
        who = cand[k].j;
        kind = EventKind::Pair;
      }
      if (tt[1] < best) {
        best = tt[1];
        who = cand[k + 1].j;
        kind = EventKind::Pair;
      }
    }
#endif
    for (; k < n; ++k) {
      const Disk& dj = disk[cand[k].j];
      const double t = pair_collision_time_branchless(
          di.x - (dj.x + dj.vx * since + shx[cand[k].k]), di.y - (dj.y + dj.vy * since + shy[cand[k].k]),
          di.vx - dj.vx, di.vy - dj.vy, ri + (mixed ? body[cand[k].j].r : ur));
      if (t < best) {
        best = t;
        who = cand[k].j;
        kind = EventKind::Pair;
      }
    }
    best_out = best;
    who_out = who;
    kind_out = kind;
  }

  void scan_agents(int i, int c, double& best, int& who, EventKind& kind) const {
    if (s_.cell_agents.empty()) return;  // no agent in any cell: skip the per-cell lookup
    const int begin = s_.cell_agent_begin[c], end = s_.cell_agent_begin[c + 1];
    if (begin == end) return;
    const Disk now_i = now_record(i);
    const DiskBody& b = s_.body[i];
    const DiskNow d{now_i.x, now_i.y, now_i.vx, now_i.vy, b.r, b.m, b.w, now()};
    for (int k = begin; k < end; ++k) {
      const int a = s_.cell_agents[k];
      const double t = s_.agents[a]->event_time(s_, i, d);
      if (t < best) {
        best = t;
        who = a;
        kind = EventKind::Agent;
      }
    }
  }

  // The 3×3 block of cells around cell `centre` (§2.2), in scan order, with image shifts.
  static constexpr double kNoShift[9] = {};  // the image shifts of a block away from periodic edges
  struct Block {
    int centre = -1;
    int cells[9];
    double shx[9], shy[9];  // set only where `shifted`
    int nc = 0;
    bool shifted = false;  // some shift is not zero (a periodic edge)
  };
  void block(int c, Block& b) const {
    const CellGrid& g = s_.grid;
    const int ix = g.ix(c), iy = g.iy(c);
    b.centre = c;
    b.nc = 0;
    b.shifted = false;
    if (ix > 0 && ix + 1 < g.nx() && iy > 0 && iy + 1 < g.ny()) {
      // Away from the edges (nearly always): the 3×3 block in the same order, no images
      // (the shifts are left unset: not `shifted`, so no scan reads them).
      for (int ky = -1; ky <= 1; ++ky)
        for (int kx = -1; kx <= 1; ++kx) b.cells[b.nc++] = c + ky * g.nx() + kx;
    } else {
      for (int ky = -1; ky <= 1; ++ky) {
        int cy = iy + ky;
        double sy = 0.0;
        if (!wrap(cy, g.ny(), g.periodic_y(), g.ly(), sy)) continue;
        for (int kx = -1; kx <= 1; ++kx) {
          int cx = ix + kx;
          double sx = 0.0;
          if (!wrap(cx, g.nx(), g.periodic_x(), g.lx(), sx)) continue;
          b.cells[b.nc] = g.index(cx, cy);
          b.shx[b.nc] = sx;
          b.shy[b.nc++] = sy;
          b.shifted |= sx != 0.0 || sy != 0.0;
        }
      }
    }
  }

  // Every disk present predicted afresh, with event records for them and n_timers timers
  // (the timers' unscheduled).
  void predict_all(int n_timers) {
    s_.reset_events(s_.size(), n_timers);
    for (int i = 0; i < s_.size(); ++i)
      if (s_.present(i)) predict_full(i);
  }
  // Full prediction for disk i over its 3×3 neighbourhood (§2.2) and its cell's agents.
  void predict_full(int i) {
    Block b;
    block(s_.grid.cell(i), b);
    predict_listed(i, b, cand_.data(), gather(i, b.cells, b.nc, cand_));
  }
  // The same from disk i's candidates already listed: cand[0..n) from the block b around its cell.
  void predict_listed(int i, const Block& b, const Candidate* cand, int n) {
    const Prediction p = earliest(i, b, cand, n);
    schedule(i, p.best, p.who, p.kind);
  }
  // Disk i's earliest pair or agent event (before schedule stores it).
  struct Prediction {
    double best = kNever;
    int who = -1;
    EventKind kind = EventKind::None;
  };
  Prediction earliest(int i, const Block& b, const Candidate* cand, int n) {
    Prediction p;
    evaluate(now_record(i), s_.radius(i), cand, n, b.shx, b.shy, b.shifted, p.best, p.who, p.kind);
    scan_agents(i, b.centre, p.best, p.who, p.kind);
    return p;
  }
  // predict_full(i), cal_.update(i), predict_full(j), cal_.update(j) — the two parties of a
  // collision — in two halves: list_parties lists the candidates of both neighbourhoods
  // (before the collision: its cache misses then overlap those of the parties' records),
  // predict_parties computes the records. The same records: membership does not change
  // in a collision, each candidate's record is read when evaluated, and a prediction
  // reads nothing the other's record or calendar update changes.
  void list_parties(int i, int j) {
    const CellGrid& g = s_.grid;
    Party& a = party_[0];
    Party& b = party_[1];
    block(g.cell(i), a.block);
    block(g.cell(j), b.block);
    for (int k = 0; k < b.block.nc; ++k) __builtin_prefetch(g.cell_slots(b.block.cells[k]).address());
    a.n = gather(i, a.block.cells, a.block.nc, a.cand);
    b.n = gather(j, b.block.cells, b.block.nc, b.cand);
    __builtin_prefetch(&s_.event[j], 1);  // written by predict_parties
  }
  // Both parties are evaluated before either is stored: schedule reads the partner's
  // counter, a cache miss at N ≳ 10^6 (the counters outgrow the L2 cache), and the second
  // evaluation overlaps it (with the gather's prefetch of the candidates' counters, +8 % at
  // 1.4 × 10^6, measured in alternating windows of one run).
  void predict_parties(int i, int j) {
    const Prediction pi = earliest(i, party_[0].block, party_[0].cand.data(), party_[0].n);
    const Prediction pj = earliest(j, party_[1].block, party_[1].cand.data(), party_[1].n);
    schedule(i, pi.best, pi.who, pi.kind);
    reschedule(i);
    schedule(j, pj.best, pj.who, pj.kind);
    reschedule(j);
  }

  // Stores disk i's next event: its pair (or agent) event in `best` from now, with `who`
  // (kind None when best is kNever), or the next crossing of a wall of its own cell, the
  // key being the earlier of the two (the cell index is authoritative; the position may
  // sit an ulp outside after round-off, hence the clamp at zero). A tie goes to the
  // crossing.
  void schedule(int i, double best, int who, EventKind kind) {
    const CellGrid& g = s_.grid;
    const Disk d = now_record(i);
    const int c = g.cell(i);
    const int ix = g.ix(c), iy = g.iy(c);
    double tx = kNever, ty = kNever;
    std::uint8_t dx = 0, dy = 2;
    if (d.vx > 0.0) {
      if (ix + 1 < g.nx() || g.periodic_x()) tx = ((ix + 1) * g.width() - d.x) / d.vx;
    } else if (d.vx < 0.0) {
      if (ix > 0 || g.periodic_x()) tx = (ix * g.width() - d.x) / d.vx;
      dx = 1;
    }
    if (d.vy > 0.0) {
      if (iy + 1 < g.ny() || g.periodic_y()) ty = ((iy + 1) * g.height() - d.y) / d.vy;
    } else if (d.vy < 0.0) {
      if (iy > 0 || g.periodic_y()) ty = (iy * g.height() - d.y) / d.vy;
      dy = 3;
    }
    const bool use_x = tx <= ty;
    const double t = std::max(0.0, use_x ? tx : ty);
    const double pair_time = now() + best, cross_time = now() + t;
    if (best == kNever) kind = EventKind::None;
    // Built in registers and stored whole: setting the bit fields in place would first
    // read the old record, a cache miss.
    NextEvent ev;
    ev.key = std::min(pair_time, cross_time);
    ev.partner_count = kind == EventKind::Pair ? s_.counter[who] : 0u;
    ev.partner = kind == EventKind::None ? 0u : static_cast<std::uint32_t>(who);
    ev.kind = kind;
    ev.cross_dir = use_x ? dx : dy;
    ev.crossing = cross_time <= pair_time;
    s_.event[i] = ev;
    if (kind == EventKind::Agent) s_.agent_time[i] = pair_time;
  }

  // Disk i's record with its position now instead of at the epoch.
  Disk now_record(int i) const {
    const Disk& d = s_.disk[i];
    const double dt = since_epoch();
    return Disk{d.x + d.vx * dt, d.y + d.vy * dt, d.vx, d.vy};
  }
  // r_i − r_j now, j seen from i's cell (minimum image by cell offsets): a collision's
  // normal and virial arm.
  void separation_now(int i, int j, double& rx, double& ry) const {
    double sx, sy;
    s_.grid.image_shift(s_.grid.cell(i), s_.grid.cell(j), sx, sy);
    const Disk a = now_record(i), b = now_record(j);
    rx = a.x - (b.x + sx);
    ry = a.y - (b.y + sy);
  }

  SystemState& s_;
  Calendar cal_;
  std::vector<int> around_;      // scratch: disks around newcomers
  std::vector<Candidate> cand_;  // scratch of scan_cells
  // A collision's parties, listed by list_parties: block, candidates and their number.
  struct Party {
    Block block;
    std::vector<Candidate> cand;
    int n = 0;
  };
  Party party_[2];
  CollisionParams tc_rule_;      // scratch of tc_elastic_rule
  // A lane's own (kLane): its clock and books, the link to the other lane, its number.
  LaneBooks books_;
  LaneBookLog book_log_;  // lane_run's
  LaneLink* link_ = nullptr;
  int me_ = 0;
  // owns(): a bit a disk, so that the check at every event stays in cache (a byte a disk
  // missed it at 10^5 disks).
  std::vector<std::uint64_t> mine_;
  // The event being processed is in the order of one loop (always, outside lane_run).
  bool serial_ = true;
  int deferred_ = -1;     // the entry found to need that order (process returned false)
  bool resting_ = false;  // lane_settle: records only, no calendar or mail
  bool tc_on_ = false, maybe_frozen_ = false;  // lane_start
  double tc_tau_ = 0.0;
  EventOrder horizon_;  // the latest event this lane did in this run (late_conflict)
};

}  // namespace grainflow::ed
