// The ED event loop on two lanes (LaneLink): the box is cut into two bands of cell rows,
// each lane runs the events of its band on its own clock and books, and edge events are
// ordered between the lanes so that every disk sees the events it takes part in in the
// order of one loop: the disks come out with the same bits whether the lanes run on two
// threads or in their merged order on one (a conservative parallel discrete-event scheme;
// cf. Miller & Luding, J. Comput. Phys. 193 (2004) 306, and Lubachevsky 1991).
//
// The lanes move the common epoch (SystemState::rebase) only between runs, at times the
// loop fixes in advance (about rebase_period() events after the epoch, at the rate the
// event records give), never at an event count: so its bits differ from the one-lane
// loop's, which rebases at counts, but not with the number of threads, nor with a
// checkpoint taken between runs (the records are in it). The books (kinetic energy,
// virial sums, kT integral) are summed per lane in the order of one loop and added in
// lane order at each stop: the same bits on one thread and two, though a lane may take an
// event the other lane sent it after later ones of its own that it does not touch (the
// sums are then done again in order: LaneBookLog).
//
// Everything the one loop runs runs here: particle agents (walls, obstacles, the stream's
// piston, filter, inlet and outlet planes) act in the order of one loop between the lanes
// (LaneLink orders their events like edge events), on the state at the lane's time; timers
// (samplers, thermostats, phases, the dispenser's recharge, the inlet) act at stops between
// the lanes' runs, where the disks they add are settled; the TC model's overlap removals
// are done in the order of one loop too (tc_verdict), the raised cutoff taking effect at
// the next stop. A collision observer is refused.
//
// Hard disks give no look-ahead: a chain of collisions can carry an event the other lane
// mailed late into rows this lane already ran ahead in. A lane detects where that may have
// happened (LaneLink's stamps) and the run between the two stops is done again from a copy
// kept at its start, in the merged order, so the bits never depend on the threads.
#pragma once
#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <string>
#include <thread>

#include "engine/core/error.hpp"
#include "engine/ed/bucket_calendar.hpp"
#include "engine/ed/event_loop.hpp"
#include "engine/io/archive.hpp"

namespace grainflow::ed {

class ParallelLoop final : public EventLoopBase {
public:
  using Lane = EventLoop<BucketCalendar, true>;
  // threads: 2 runs the lanes at once, 1 in their merged order on this thread.
  ParallelLoop(SystemState& s, int threads) : s_(s), threads_(threads) {
    if (threads != 1 && threads != 2) throw Error("ed: the parallel loop runs on 1 or 2 threads, not " + std::to_string(threads));
    for (int k = 0; k < LaneLink::kLanes; ++k) {
      lane_[k] = std::make_unique<Lane>(s_, BucketCalendar::spreading_ahead());
      lane_[k]->lane_attach(&link_, k);
    }
  }

  void start() override {
    check_supported();
    configure_link();
    const int n = s_.size(), nt = static_cast<int>(s_.timers.size());
    lane_[0]->lane_start(s_.now());
    lane_[0]->lane_predict_all(nt);
    s_.clear_changes();
    s_.clear_touched();
    s_.clear_rescheduled();  // every timer is asked below
    for (int a = 0; a < nt; ++a) s_.event[n + a].key = std::max(s_.now(), s_.timers[a]->event_time(s_));
    fill();
    warm_start_copy();
  }
  void resume() override {
    check_supported();
    configure_link();
    fill();
    warm_start_copy();
  }

  void run_until(double t) override { run_until(t, ~std::uint64_t{0}); }
  // Stops at the first rebase stop after max_events events (the clock is then at that
  // stop, not at an event): a run cut short still ends at a time both lanes reached.
  // Timers run at stops too: the lanes do every disk event up to a timer's time (a timer
  // comes after the disks' events of its time, as in one loop), then it acts on the state
  // at rest.
  bool run_until(double t, std::uint64_t max_events) override {
    settle_outside_actions();
    plan_rebase();
    const std::uint64_t e0 = s_.stats.events;
    for (;;) {
      const EventOrder timer = next_timer();
      const double stop = std::min({t, next_rebase_, timer.key});
      run_lanes(stop);
      if (timer.key == stop) run_timers(stop);
      if (stop == next_rebase_) rebase_stop();
      if (stop >= t) return true;
      if (s_.stats.events - e0 >= max_events) return false;
    }
  }
  // Exactly n events, in the merged order on this thread.
  std::uint64_t advance(std::uint64_t n) override {
    settle_outside_actions();
    plan_rebase();
    start_lanes();
    std::uint64_t k = 0;
    double last = s_.now();
    while (k < n) {
      const auto [disk, lane] = merged_next();
      const EventOrder timer = next_timer();
      const EventOrder o = timer < disk ? timer : disk;
      if (o.e < 0) break;
      if (o.key > next_rebase_) {
        finish_lanes(next_rebase_);
        rebase_stop();
        start_lanes();
        last = s_.now();
        continue;
      }
      if (o.e == timer.e) {
        finish_lanes(o.key);
        timer_event(o.e - s_.size());
        start_lanes();
      } else {
        lane_[lane]->lane_process(o.e);
      }
      last = o.key;
      ++k;
    }
    finish_lanes(last);
    return k;
  }
  double next_event_time() override {
    const EventOrder disk = merged_next().first, timer = next_timer();
    const double t = std::min(disk.key, timer.key);
    return std::isfinite(t) ? t : kNever;
  }
  std::size_t calendar_bytes() const override { return lane_[0]->calendar_bytes() + lane_[1]->calendar_bytes(); }
  const char* calendar_name() const override { return BucketCalendar::kName; }
  LaneRuns lane_runs() const override { return {runs_, redone_}; }
  std::size_t lane_bytes() const override { return start_.bytes() + start_agents_.capacity() + link_.bytes(); }

private:
  void check_supported() const {
    if (s_.grid.ny() < LaneLink::kMinRows)
      throw Error("ed: the two-lane loop needs at least " + std::to_string(LaneLink::kMinRows) +
                  " rows of cells across the box; this system has " + std::to_string(s_.grid.ny()) +
                  "; run it with lanes = threads = 1");
  }
  // The cut and the stamps for the grid as it is, the mailboxes and published events empty.
  void configure_link() { link_.configure(s_.grid.ny(), s_.grid.periodic_y(), s_.grid.size()); }
  void fill() {
    for (auto& l : lane_) l->lane_fill();
  }
  // What was changed between runs (set_velocity, a timer switched): settled as after a
  // timer's action. An observer of collisions (set after the start) is refused here, before
  // any event: the lanes would not call it.
  void settle_outside_actions() {
    if (on_collision) throw Error("ed: the two-lane loop does not trace collisions; run with lanes = threads = 1");
    settle();
  }
  // Disks an action added (and the disks around them), and disks whose velocity it changed
  // (SystemState::touched), are predicted again and the calendars refilled; timers it
  // switched (SystemState::reschedule) are asked again. (A timer's action, or one from
  // outside between runs: the lanes are at rest.)
  void settle() {
    const bool changed = s_.grown() || !s_.added().empty() || !s_.removed().empty();
    if (!changed && s_.touched().empty()) {
      reschedule_timers();
      return;
    }
    lane_[0]->lane_start(s_.now());
    if (changed) lane_[0]->lane_settle();
    for (int j : s_.touched())
      if (s_.present(j)) lane_[0]->lane_predict(j);
    s_.clear_touched();
    reschedule_timers();  // after the slots settled: the timers' records follow the disks'
    fill();
  }
  void reschedule_timers() {
    const int n = s_.size();
    for (int b : s_.rescheduled()) s_.event[n + b].key = std::max(s_.now(), s_.timers[b]->event_time(s_));
    s_.clear_rescheduled();
  }

  // The earliest timer event (key, entry), or none.
  EventOrder next_timer() const {
    EventOrder o;
    const int n = s_.size();
    for (int a = 0; a < static_cast<int>(s_.timers.size()); ++a) {
      const EventOrder c{s_.event[n + a].key, n + a};
      if (c < o) o = c;
    }
    return o;
  }
  // Every timer due at t (the clock is at t, the lanes at rest), in the loop's order.
  void run_timers(double t) {
    for (EventOrder o = next_timer(); o.key <= t; o = next_timer()) timer_event(o.e - s_.size());
  }
  void timer_event(int a) {
    ++s_.stats.events;
    ++s_.stats.timer_events;
    TimerAgent& ag = *s_.timers[a];
    ag.action(s_);
    s_.event[s_.size() + a].key = std::max(s_.now(), ag.event_time(s_));
    settle();
  }

  void start_lanes() {
    for (auto& l : lane_) l->lane_start(s_.now());
  }
  void finish_lanes(double t) {
    LaneBooks books[LaneLink::kLanes];
    for (int k = 0; k < LaneLink::kLanes; ++k) books[k] = lane_[k]->lane_books();
    s_.absorb_lanes(t, books, LaneLink::kLanes);
  }
  // The earlier of the lanes' next events, and its lane (the mail each lane has is taken in).
  std::pair<EventOrder, int> merged_next() {
    EventOrder o[LaneLink::kLanes];
    for (int k = 0; k < LaneLink::kLanes; ++k) {
      o[k] = lane_[k]->lane_next();
      link_.taken(k);
    }
    return o[1] < o[0] ? std::pair{o[1], 1} : std::pair{o[0], 0};
  }
  // Every event up to t (key ≤ t), then the clocks and books at t. On two threads, a run
  // in which a lane found the order of one loop broken (LaneLink::violate: a late event)
  // is done again from its start in the merged order, which is the order of reference.
  void run_lanes(double t) {
    start_lanes();
    if (threads_ == 2) {
      keep_start();
      // Each lane's next event is published before either starts: a lane judges its edge
      // events by what the other has published, which must never be later than its next.
      for (int k = 0; k < LaneLink::kLanes; ++k) {
        link_.publish(k, lane_[k]->lane_next());
        link_.taken(k);
      }
      // An error in a lane (an agent's action that throws) stops both and is thrown here.
      std::exception_ptr failed[LaneLink::kLanes];
      auto lane = [this, t, &failed](int k) {
        try {
          lane_[k]->lane_run(t);
        } catch (...) {
          failed[k] = std::current_exception();
          link_.violate();
        }
      };
      std::thread other(lane, 1);
      lane(0);
      other.join();
      for (const auto& f : failed)
        if (f) std::rethrow_exception(f);
      ++runs_;
      if (!link_.violated()) {
        finish_lanes(t);
        return;
      }
      ++redone_;
      back_to_start();
    }
    for (;;) {
      const auto [o, lane] = merged_next();
      if (!(o.key <= t)) break;
      lane_[lane]->lane_process(o.e);
    }
    finish_lanes(t);
  }
  // The state, agents and timers at the start of a run on two threads (the buffers are
  // kept: after the first run, a copy without allocation).
  void keep_start() {
    s_.snapshot(start_);
    io::ArchiveWriter w;
    for (const auto& a : s_.agents) a->save(w);
    for (const auto& tm : s_.timers) tm->save(w);
    start_agents_ = w.take();
  }
  // The copy's buffers are allocated and faulted in at the start, not in the first run (at
  // 10^6 disks the kernel's zeroing of ~170 MB was 7 % of a short run's time).
  void warm_start_copy() {
    if (threads_ == 2) keep_start();
  }
  void back_to_start() {
    io::ArchiveReader r(start_agents_, "the agents at the start of the run");
    for (const auto& a : s_.agents) a->load(r);
    for (const auto& tm : s_.timers) tm->load(r);
    s_.restore(std::move(start_));
    configure_link();
    fill();
    start_lanes();
  }
  // At a rebase stop (the clock at next_rebase_): the epoch moves to now, and the next
  // stop is planned.
  void rebase_stop() {
    s_.rebase();
    plan_rebase();
  }
  // The next rebase stop: kRebaseSpan × rebase_period() events after the epoch, at the
  // rate the event records give (each disk's next event comes after about the mean time to
  // it). Derived from the state alone, at the start of each run and at each stop, so that
  // a run resumed from a checkpoint plans the stops the uninterrupted one does. Each stop
  // costs a pass over the state and a copy of it (keep_start); the records' positions are
  // then up to a few collisions per disk older than the one loop's (rounding of
  // x + v·(t − epoch), far below the overlap tolerance).
  static constexpr double kRebaseSpan = 4.0;
  void plan_rebase() {
    double sum = 0.0;
    int n = 0;
    for (int i = 0; i < s_.size(); ++i)
      if (s_.present(i) && std::isfinite(s_.event[i].key)) {
        sum += s_.event[i].key - s_.now();
        ++n;
      }
    const double period = n > 0 ? sum / n * kRebaseSpan * static_cast<double>(s_.rebase_period()) / n : 0.0;
    next_rebase_ = period > 0.0 && std::isfinite(period) ? std::max(s_.now(), s_.epoch() + period) : kNever;
  }

  SystemState& s_;
  int threads_;
  LaneLink link_;
  std::unique_ptr<Lane> lane_[LaneLink::kLanes];
  double next_rebase_ = kNever;  // plan_rebase
  SystemState::Saved start_;     // keep_start
  std::string start_agents_;
  std::uint64_t runs_ = 0, redone_ = 0;
};

}  // namespace grainflow::ed
