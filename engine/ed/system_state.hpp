// The state of an ED hard-disk system as the event loop and the agents see it: disks with
// their own lazy clocks (seed 003 §2.3), per-disk next events with partner counters
// (DynamO style), the cell map (§2.2), the collision rule (§3.4) and the energy books.
#pragma once
#include <algorithm>
#include <cstddef>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "engine/core/vec.hpp"
#include "engine/ed/calendar_keys.hpp"
#include "engine/ed/cell_grid.hpp"
#include "engine/ed/collision_rule.hpp"
#include "engine/ed/event_source.hpp"
#include "engine/ed/huge_pages.hpp"
#include "engine/ed/initial_state.hpp"
#include "engine/ed/pair_collision_time.hpp"
#include "engine/ed/stats.hpp"

namespace grainflow::io {
class ArchiveWriter;
class ArchiveReader;
}  // namespace grainflow::io

namespace grainflow::ed {

// What a slot of the disk arrays holds (open stream boundaries, seed 003 §3.2–3.3).
enum class SlotState : std::uint8_t { absent = 0, present = 1, frozen = 2 };

// What a neighbourhood scan reads of each candidate, 32 bytes (two disks per cache line):
// the velocity, and the position the disk would have had at the common epoch
// (SystemState::epoch) had it moved at this velocity since. The disk's position now is
// x + vx (now − epoch): one clock for every disk instead of the seed's per-disk lazy clocks
// (§2.3), which would cost a time stamp per disk in the hot record. Only the parties of an
// event change their record, as with lazy clocks; the epoch is moved to now every so
// often (SystemState::rebase) so that (now − epoch) stays a few collision times and the
// positions keep the precision of the box's coordinates.
struct alignas(32) Disk {
  double x = 0.0, y = 0.0, vx = 0.0, vy = 0.0;
};

// What only the parties of an event read: radius, mass and spin ω_z (rough disks). A scan
// needs the candidates' radii only when the disks differ in size (SystemState::uniform_radius).
struct DiskBody {
  double r = 0.0, m = 0.0, w = 0.0;
};

// One disk removed by the TC model's overlap handling (SystemState::remove_overlapping):
// when, where (at that time), which slot, and the cutoff time τ_TC after the raise.
struct OverlapRemoval {
  double t = 0.0, x = 0.0, y = 0.0, tau_tc = 0.0;
  std::int64_t id = -1;
};

// The TC (time cutoff) model of Luding & McNamara 1998 (seed 003 ch. 5): a disk–disk
// collision is elastic in its normal part when either party's previous disk–disk collision
// happened less than `tau` ago, so that an inelastic system cannot collapse (infinitely
// many collisions in a finite time). A numerical overlap removes the offending disk and
// raises tau by `step`. On when e < 1 and tau or step is positive.
struct TimeCutoff {
  double tau = 0.0;   // τ_TC, time units; 0: every collision with the configured e
  double step = 0.0;  // added to tau at each overlap removal
  bool configured() const { return tau > 0.0 || step > 0.0; }
};

// Numerical overlap (TC model): at a collision the centres are closer than
// σ_ij (1 − kOverlapGap), i.e. r² − σ² < −2 kOverlapGap σ². Twice the overlap a built
// configuration may have (Simulation refuses initial gaps below −10^-9 σ), far above the
// round-off of a contact (≈ 10^-14 σ).
inline constexpr double kOverlapGap = 2e-9;

// How Σ m v_a v_b (xx, xy, yy) changes when a disk of mass m goes from (vx0, vy0) to
// (vx1, vy1): the kinetic-tensor books' step (SystemState, LaneBooks).
struct TensorStep {
  double xx, xy, yy;
};
inline TensorStep kinetic_tensor_step(double m, double vx0, double vy0, double vx1, double vy1) {
  return {m * (vx1 * vx1 - vx0 * vx0), m * (vx1 * vy1 - vx0 * vy0), m * (vy1 * vy1 - vy0 * vy0)};
}

struct LaneBooks;

// The order of one loop for a lane's sums on two threads. A lane sums its books event by
// event; on two threads it may take an event the other lane mailed it after later ones of
// its own (a late event, ParallelLoop), and floating-point sums taken in another order
// differ in their last bits. So, on two threads, a lane also logs each addition (with
// its event's place in the order of one loop, (key, entry)) since the last point where its
// sums were final; a late event has the sums done again from that point, each event's
// additions in the order of one loop: the same operations in the same order as on one
// thread, so the same bits. A point is final after an edge event that was not late (the
// other lane had passed it and its mail was in: nothing can come before it any more), or
// when the other lane is past everything this lane did (a long stretch without edge
// events: EventLoop::lane_run).
// Late events are rare (one in about 5 × 10^6 events of the elastic box), so the redoing
// costs nothing; the log usually spans the few dozen events between two edge events, and
// is cut past kLogCut events where no edge event comes (EventLoop::lane_run).
class LaneBookLog {
public:
  void settle(const LaneBooks& b);  // b's sums are final: the log starts afresh
  void begin_event(double key, int e) { events_.push_back(Event{key, e, 0.0, values_.size(), kinds_.size()}); }
  std::size_t events() const { return events_.size(); }
  void kinetic(double now, double dk, double drot, double dpx, double dpy) {
    note(kKinetic, now);
    values_.insert(values_.end(), {dk, drot, dpx, dpy});
  }
  void tensor(double now, double xx, double xy, double yy) {
    note(kTensor, now);
    values_.insert(values_.end(), {xx, xy, yy});
  }
  void virial(double rx, double ry, double jx, double jy) {
    note(kVirial, events_.back().now);
    values_.insert(values_.end(), {rx, ry, jx, jy});
  }
  // The last event began out of its order: b's sums are done again from the final ones,
  // event by event in the order (key, entry).
  void reorder_last(LaneBooks& b);

private:
  // Each addition: its kind, then its values (4, 3, 4) in one stream; the clock it saw is
  // its event's.
  enum Kind : std::uint8_t { kKinetic, kTensor, kVirial };
  struct Event {
    double key;
    int e;
    double now;                    // the clock its additions saw
    std::size_t values, kinds;     // where its values and kinds begin
    std::size_t n_kinds = 0;       // its additions
    bool before(const Event& o) const { return key < o.key || (key == o.key && e < o.e); }
  };
  void note(Kind k, double now) {
    kinds_.push_back(k);
    Event& ev = events_.back();
    ev.now = now;
    ++ev.n_kinds;
  }
  // The sums of LaneBooks, as at the last final point.
  struct Sums {
    double kin = 0.0, rot = 0.0, px = 0.0, py = 0.0, kxx = 0.0, kxy = 0.0, kyy = 0.0;
    double kin_t = 0.0, kxx_t = 0.0, kxy_t = 0.0, kyy_t = 0.0;
    double virial = 0.0, virial_xx = 0.0, virial_xy = 0.0, virial_yy = 0.0;
  };
  Sums settled_;
  std::vector<Event> events_;
  std::vector<double> values_;
  std::vector<std::uint8_t> kinds_;
};

// What one lane of the parallel loop (ParallelLoop) keeps while it runs on its own: its
// clock, its counts and sums (as Stats, from zero), and the changes it made to the energy,
// momentum and kinetic-tensor books, with their integrals over its time since it left
// the state's clock (SystemState::absorb_lanes adds them up). log: on two threads, where
// each addition is noted too (LaneBookLog).
struct LaneBooks {
  double now = 0.0;
  Stats stats;
  double kin = 0.0, rot = 0.0, px = 0.0, py = 0.0, kxx = 0.0, kxy = 0.0, kyy = 0.0;
  // Σ change × its time, so that ∫ change dt up to t is change·t − this whatever the order
  // the lane took its events in (it may take an event the other lane sent it after later
  // ones of its own that the event does not touch).
  double kin_t = 0.0, kxx_t = 0.0, kxy_t = 0.0, kyy_t = 0.0;
  LaneBookLog* log = nullptr;
  void start(double t) {
    *this = LaneBooks{};
    now = t;
  }
  // The clock is the event's time, not the latest time seen (see kin_t).
  void advance_clock(double t) { now = t; }
  void add_kinetic(double dk, double drot, double dpx, double dpy) {
    if (log) log->kinetic(now, dk, drot, dpx, dpy);
    kin += dk;
    kin_t += dk * now;
    rot += drot;
    px += dpx;
    py += dpy;
  }
  void add_kinetic_tensor(double m, double vx0, double vy0, double vx1, double vy1) {
    add_tensor(kinetic_tensor_step(m, vx0, vy0, vx1, vy1));
  }
  void add_tensor(const TensorStep& d) {
    if (log) log->tensor(now, d.xx, d.xy, d.yy);
    kxx += d.xx;
    kxy += d.xy;
    kyy += d.yy;
    kxx_t += d.xx * now;
    kxy_t += d.xy * now;
    kyy_t += d.yy * now;
  }
  void add_virial(double rx, double ry, double jx, double jy) {
    if (log) log->virial(rx, ry, jx, jy);
    ed::add_virial(stats, rx, ry, jx, jy);
  }
};

// A disk as an agent sees it at time t (a copy: SystemState::disk_now, or the loop's).
struct DiskNow {
  double x = 0.0, y = 0.0, vx = 0.0, vy = 0.0, r = 0.0, m = 0.0, w = 0.0, t = 0.0;
};

// What a disk's scheduled non-crossing event is.
enum class EventKind : std::uint8_t { None = 0, Pair = 1, Agent = 2 };

// A calendar entry's scheduled event, everything the loop reads when the entry's turn
// comes, in 16 bytes: one cache miss, not one per field, and four records to a line (at
// N ≳ 10^5 the loop waits on memory, not arithmetic). A disk has two candidate events,
// its earliest pair (or agent) event and its next cell-wall crossing; key is the earlier
// of the two, and the later one's time is not kept in it: whatever a pair event does, the
// disk is predicted afresh, and a crossing that comes first computes the held pair event's
// time again from the partner alone (EventLoop::crossing), or reads the held agent event's
// from SystemState::agent_time. A timer agent's entry uses key only.
struct alignas(16) NextEvent {
  double key = kNever;                  // calendar key: when the entry's next event happens
  std::uint32_t partner_count = 0;      // partner's counter when predicted (Pair)
  std::uint32_t partner : 24 = 0;       // disk id (Pair) or agent id (Agent); CellGrid::kMaxDisks
  EventKind kind : 2 = EventKind::None;
  std::uint32_t cross_dir : 2 = 0;      // 0 +x, 1 −x, 2 +y, 3 −y
  bool crossing : 1 = false;            // the key is a cell-wall crossing (else the pair event)
};
static_assert(sizeof(NextEvent) == 16 && CellGrid::kMaxDisks <= (1 << 24), "a partner's id must fit 24 bits");

class SystemState {
public:
  // ---- disks -------------------------------------------------------------------------
  HugeVector<Disk> disk;
  HugeVector<DiskBody> body;
  // Bumped whenever the disk's velocity changes (or it comes/goes), so that events naming
  // it turn stale. Kept apart from the event records: at 4 bytes a disk the array stays
  // in cache, where a record would cost a memory access per neighbour predicted.
  HugeVector<std::uint32_t> counter;
  std::vector<SlotState> slot;
  // Each slot's disk's persistent id, as LAMMPS calls it a tag: what particle files write
  // as `id`. A disk keeps it for as long as it is in the system — through collisions,
  // freezing, turning back at an outlet or a filter, and renumbering of slots (compaction,
  // Simulation::reorder_disks) —, and a disk added later (an inlet, the dispenser) gets
  // the next one never used, even when it takes the slot of a disk that left: an id names
  // one disk's whole stay, never two disks, so a trajectory followed by id never jumps.
  // Bookkeeping only: no event depends on it. 0 in a slot never used.
  std::vector<std::int64_t> tag;
  std::int64_t next_tag() const { return next_tag_; }
  // Sets the tags of the size() disks built (the builder): 1, 2, … or the given ones.
  void reset_tags(std::vector<std::int64_t> tags, std::int64_t next) {
    tag = std::move(tags);
    next_tag_ = next;
  }
  int size() const { return static_cast<int>(disk.size()); }

  // Disks enter and leave (open stream boundaries, seed 003 §3.2–3.3). Ids are slots:
  // size() is the number of slots, count() the disks present; a removed id may be reused.
  // Callable from inside ParticleAgent::action and TimerAgent::action.
  int add_disk(const DiskInit& d);   // placed at now(); returns its id. The loop predicts it after the
                                     // action and re-predicts every disk in the 3×3 cells around it.
  void remove_disk(int i);           // leaves now: out of the cell map and the calendar
  bool present(int i) const { return slot[i] != SlotState::absent; }
  int count() const { return n_present_; }  // disks present (frozen ones included)
  // Infinitely heavy disk moving at v from now on (the outlet filter, Fig. 3.8): other disks
  // bounce off it as off a moving wall; it is left out of kT, energy and momentum books.
  void freeze(int i, double vx, double vy);
  bool frozen(int i) const { return slot[i] == SlotState::frozen; }
  int frozen_count() const { return n_frozen_; }
  int mobile_count() const { return n_present_ - n_frozen_; }  // the disks in the books
  // Asks the loop to re-predict disk i after the current action without changing it (an
  // agent that moved, e.g. the dispenser piston jumping back).
  void repredict(int i) { touched_.push_back(i); }
  // Asks the loop to ask timer `t` (one of `timers`) for its next time again after the
  // current action: an agent that switched another on or off (a phase turning the
  // thermostat on). Callable from inside an agent's or timer's action, or between runs
  // (settled when the next run starts; a checkpoint must not be taken in between).
  void reschedule(const TimerAgent* t);
  const std::vector<int>& rescheduled() const { return rescheduled_; }
  void clear_rescheduled() { rescheduled_.clear(); }
  // Diameters a disk added later may have: the cell map was sized for [min, max].
  void set_diameter_range(double dmin, double dmax) { dmin_ = dmin; dmax_ = dmax; }
  // Called by the builder after filling disk/body for size() disks: the epoch is now and
  // the radii are looked at.
  void reset_disks();
  // Fills the slot bookkeeping for size() disks (called by the builder): all present, or
  // the given states (one per slot, none absent).
  void reset_slots(std::vector<SlotState> states = {});

  // ---- next event per calendar entry: the disks, then one per timer agent -------------
  HugeVector<NextEvent> event;
  // The time of each disk slot's event when it is an agent's (kind Agent; else unused),
  // for a crossing that comes first: an agent is not asked again, since it may ignore a
  // disk it takes for one it has just acted on (one that sits on its plane, say), which a
  // crossing at the same moment would be. Apart from the records, and touched only by
  // disks whose next event is an agent's.
  HugeVector<double> agent_time;
  // Sizes event for n disks and n_timers timers, every event unscheduled.
  void reset_events(int n, int n_timers) {
    event.assign(static_cast<std::size_t>(n) + static_cast<std::size_t>(n_timers), NextEvent{});
    agent_time.assign(static_cast<std::size_t>(n), kNever);
    events_ready_ = true;
  }

  CalendarKeys calendar_keys() const {
    static_assert(offsetof(NextEvent, key) == 0 && sizeof(NextEvent) % sizeof(double) == 0);
    return {reinterpret_cast<const double*>(event.data()), sizeof(NextEvent) / sizeof(double)};
  }

  CellGrid grid;
  CollisionParams rule;
  std::vector<std::unique_ptr<ParticleAgent>> agents;
  std::vector<std::unique_ptr<TimerAgent>> timers;
  // Agents per cell in CSR form: agents of cell c are cell_agents[cell_agent_begin[c] ..
  // cell_agent_begin[c+1]).
  std::vector<std::int32_t> cell_agent_begin, cell_agents;

  Stats stats;

  // ---- TC model (seed 003 ch. 5, Luding & McNamara 1998) ------------------------------
  TimeCutoff tc;
  // The TC model is on: inelastic (rule.e < 1) and a cutoff configured. Only then does
  // the loop read or write last_collision (elastic runs never touch it).
  bool tc_on() const { return rule.e < 1.0 && tc.configured(); }
  // Time of each slot's previous disk–disk collision (−∞: none yet). Empty until the TC
  // model first needs it (then sized to size() by tc_times()); compacted with the disks
  // and reset for a disk added into a slot.
  std::vector<double> last_collision;
  std::vector<double>& tc_times() {
    if (last_collision.size() != disk.size()) last_collision.resize(disk.size(), -kNever);
    return last_collision;
  }
  // Every overlap removal so far, in order.
  std::vector<OverlapRemoval> overlap_log;
  // Removes disk i as numerically overlapping (TC model): as remove_disk, but counted in
  // stats.removed_overlap (not stats.removed), logged with its position now, and the
  // cutoff raised by tc.step. Callable where remove_disk is (the loop settles it).
  void remove_overlapping(int i);

  double now() const { return now_; }
  double area() const { return grid.lx() * grid.ly(); }

  // ---- the common epoch of the disk records (Disk) -----------------------------------
  double epoch() const { return epoch_; }
  // Time since the epoch: a disk is at x + vx · since_epoch() now.
  double since_epoch() const { return now_ - epoch_; }
  // Position of disk i at the current time.
  Vec2 position_now(int i) const {
    const Disk& d = disk[i];
    const double dt = now_ - epoch_;
    return {d.x + d.vx * dt, d.y + d.vy * dt};
  }
  // Disk i now: position, velocity, radius, mass, spin.
  DiskNow disk_now(int i) const {
    const Disk& d = disk[i];
    const DiskBody& b = body[i];
    const double dt = now_ - epoch_;
    return {d.x + d.vx * dt, d.y + d.vy * dt, d.vx, d.vy, b.r, b.m, b.w, now_};
  }
  // Gives disk i a new velocity from now on, its path continuous at now: the epoch position
  // moves by (v_old − v_new)(now − epoch). Books, counter and re-prediction are the caller's
  // (set_velocity does all of it).
  void assign_velocity(int i, double vx, double vy) { assign_velocity(i, vx, vy, now_ - epoch_); }
  // The same at `dt` after the epoch (a lane of the parallel loop keeps its own clock).
  void assign_velocity(int i, double vx, double vy, double dt) {
    Disk& d = disk[i];
    d.x += (d.vx - vx) * dt;
    d.y += (d.vy - vy) * dt;
    d.vx = vx;
    d.vy = vy;
  }
  // Moves the epoch to now: every record then holds its disk's current position. Changes
  // no event; the loop calls it every rebase_period() events, and Simulation::synchronise
  // (before drawing or reading positions).
  void rebase();
  std::uint64_t rebase_period() const { return std::max<std::uint64_t>(4096, 2 * disk.size()); }
  // The radius every disk has had so far: 0 when they differ (then a scan reads each
  // candidate's radius from body), −1 before the first disk.
  double uniform_radius() const { return uniform_r_; }
  // The same for the mass: with one radius, one mass and smooth disks a collision needs
  // nothing from the bodies (EventLoop::collide), which saves a cache line per party.
  double uniform_mass() const { return uniform_m_; }
  // Disk i's radius, without reading its body when all disks have one.
  double radius(int i) const { return uniform_r_ > 0.0 ? uniform_r_ : body[i].r; }
  // Smooth disks of one radius and one mass: the loop's collisions and scans then read
  // nothing from the bodies (agents and frozen disks still do).
  bool plain_disks() const { return rule.smooth() && uniform_m_ > 0.0 && uniform_r_ > 0.0; }
  double inertia(int i) const { return rule.q * body[i].m * body[i].r * body[i].r; }

  // The way agents change a disk's velocity: keeps energy/momentum books and counters
  // right and asks the loop to re-predict the disk. Synchronises the disk first.
  void set_velocity(int i, double vx, double vy);
  void set_velocity(int i, double vx, double vy, double w);
  const std::vector<int>& touched() const { return touched_; }
  void clear_touched() { touched_.clear(); }

  // Energy and momentum books (kept incrementally; recompute() makes them exact again).
  double kinetic() const { return kin_; }          // translational Σ m v²/2
  double rotational() const { return rot_; }       // Σ I ω²/2
  Vec2 momentum() const { return {px_, py_}; }
  double total_mass() const { return mtot_; }
  void recompute_books();
  // Granular temperature from peculiar velocities (seed 003 Eq. 4.9 with i = 2):
  // kT = Σ m |v − V|² / (2N), V the mass-averaged velocity.
  double kT() const {
    const int n = mobile_count();
    return n ? (kin_ - 0.5 * (px_ * px_ + py_ * py_) / mtot_) / n : 0.0;
  }
  // Σ m v_a v_b (xx, xy, yy; lab frame) over the mobile disks, kept beside kinetic().
  std::array<double, 3> kinetic_tensor() const { return {kxx_, kxy_, kyy_}; }
  // The tensor book's change when a mobile disk of mass m goes from (vx0, vy0) to (vx1, vy1).
  void add_kinetic_tensor(double m, double vx0, double vy0, double vx1, double vy1) {
    const TensorStep d = kinetic_tensor_step(m, vx0, vy0, vx1, vy1);
    kxx_ += d.xx;
    kxy_ += d.xy;
    kyy_ += d.yy;
  }
  // A collision's virial, scalar and tensor (Stats::virial, virial_xx/xy/yy).
  void add_virial(double rx, double ry, double jx, double jy) { ed::add_virial(stats, rx, ry, jx, jy); }
  void add_kinetic(double dk, double drot, double dpx, double dpy) {
    kin_ += dk;
    rot_ += drot;
    px_ += dpx;
    py_ += dpy;
  }

  // Rebases when the loop has processed rebase_period() events since the last time.
  void maybe_rebase() {
    if (stats.events >= next_rebase_) [[unlikely]] {
      rebase();
      next_rebase_ = stats.events + rebase_period();
    }
  }

  // Moves the clock forward, integrating kT over the interval (measurement window).
  void advance_clock(double t) {
    if (t > now_) {
      const double dt = t - now_;
      stats.kT_integral += kT() * dt;
      // The peculiar tensor Σ m v_a v_b − P_a P_b / M (as kT, whose N-fold it halves in trace).
      if (mtot_ > 0.0 && mobile_count() > 0) {
        stats.kinetic_integral_xx += (kxx_ - px_ * px_ / mtot_) * dt;
        stats.kinetic_integral_xy += (kxy_ - px_ * py_ / mtot_) * dt;
        stats.kinetic_integral_yy += (kyy_ - py_ * py_ / mtot_) * dt;
      }
      now_ = t;
    }
  }
  // Takes in what the lanes of the parallel loop did since they left this state's clock:
  // the clock moves to t (integrating kT at the books as they were, which the lanes did not
  // change), then each lane's counts, sums, book changes and their time integrals are
  // added. The momentum term of kT, and the number of mobile disks that divides it, are
  // integrated at their values when the lanes left: exact in the periodic box (momentum
  // changes only by round-off), an approximation over one run between stops where agents
  // push the disks or take them out (the state's kT at each stop is exact).
  void absorb_lanes(double t, const LaneBooks* lanes, int n_lanes);
  // For a lane of the parallel loop, whose clock and books are its own: runs `action` (an
  // agent's action on a disk, an overlap removal) as of the lane's time, the state's clock
  // reading lane.now meanwhile, and moves what it adds to the state's books into the lane's
  // (at lane.now). The lanes run such actions one at a time, in the order of one loop
  // (LaneLink), and read neither this clock nor these books otherwise.
  template <class F>
  void act_for_lane(LaneBooks& lane, F&& action) {
    const double now0 = now_;
    const double held[7] = {kin_, rot_, px_, py_, kxx_, kxy_, kyy_};
    now_ = lane.now;
    kin_ = rot_ = px_ = py_ = kxx_ = kxy_ = kyy_ = 0.0;
    action();
    lane.add_kinetic(kin_, rot_, px_, py_);
    lane.add_tensor(TensorStep{kxx_, kxy_, kyy_});
    now_ = now0;
    kin_ = held[0], rot_ = held[1], px_ = held[2], py_ = held[3], kxx_ = held[4], kxy_ = held[5], kyy_ = held[6];
  }
  void reset_measurements() {
    stats.t0 = now_;
    stats.collisions0 = stats.collisions;
    stats.kT_integral = 0.0;
    stats.virial = 0.0;
    stats.kinetic_integral_xx = stats.kinetic_integral_xy = stats.kinetic_integral_yy = 0.0;
    stats.virial_xx = stats.virial_xy = stats.virial_yy = 0.0;
  }
  Observables observables() const;

  // Rebuilds the per-cell agent lists (after agents are added or the grid changes).
  void index_agents();

  // ---- for the event loop: what the last action did to the set of disks --------------
  struct Removal {
    int id, cell;
  };
  const std::vector<int>& added() const { return added_; }
  const std::vector<Removal>& removed() const { return removed_; }
  bool grown() const { return grown_; }  // slot arrays grew: the calendar must be rebuilt
  void clear_changes() {
    added_.clear();
    removed_.clear();
    grown_ = false;
  }

  // ---- checkpoints (Simulation::save_state / load_state) ------------------------------
  // Every mutable member, verbatim: clock, books, slot counts, diameter range, the disks
  // (at the common epoch, saved with them: nothing is rebased), the bodies, the next
  // rebase, counters, slot states, the event
  // records with the agent events' times, the free-slot list (its order decides which ids are reused), the changes
  // made from outside and not yet settled by the loop (set_velocity, add_disk, … between
  // runs: kept, and settled when the next run starts, as without the checkpoint), the
  // stats, the cell map's membership, and the TC model's state (the normal restitution as
  // it stands — Simulation::set_restitution may change it —, cutoff and step, the
  // last-collision times, the overlap log), and every slot's persistent id (tag) with the
  // next one to give. Not saved: the grid geometry, the rest of the
  // collision rule, agents and their cell lists, which the identical construction rebuilds.
  struct Saved {
    double now = 0.0, kin = 0.0, rot = 0.0, px = 0.0, py = 0.0, mtot = 0.0, dmin = 0.0, dmax = 0.0;
    double kxx = 0.0, kxy = 0.0, kyy = 0.0;
    int n_present = 0, n_frozen = 0;
    bool grown = false, events_ready = false;
    double epoch = 0.0, uniform_r = 0.0, uniform_m = 0.0;
    std::uint64_t next_rebase = 0;
    HugeVector<Disk> disk;
    HugeVector<DiskBody> body;
    HugeVector<std::uint32_t> counter;
    std::vector<SlotState> slot;
    HugeVector<NextEvent> event;
    HugeVector<double> agent_time;
    std::vector<int> touched, free, added;
    std::vector<Removal> removed;
    Stats stats;
    CellGrid::Members cells;
    double e = 1.0;
    TimeCutoff tc;
    std::vector<double> last_collision;
    std::vector<OverlapRemoval> overlap_log;
    std::vector<std::int64_t> tag;
    std::int64_t next_tag = 1;
    // Bytes its arrays hold (their capacities).
    std::size_t bytes() const {
      auto b = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
      return b(disk) + b(body) + b(counter) + b(slot) + b(event) + b(agent_time) + b(touched) + b(free) + b(added) +
             b(removed) + b(cells.slots) + b(cells.cell) + b(cells.pos) + b(cells.packed) + b(last_collision) +
             b(overlap_log) + b(tag);
    }
  };
  void save(io::ArchiveWriter& w) const;
  // Reads what save() wrote into a separate record, checked against this state (grid
  // geometry, number of agents and timers) and for consistency (array sizes, slot counts,
  // free list, cell membership, event partners); throws grainflow::Error (the reader's
  // mismatch / corrupt / truncated) and changes nothing when it does not fit.
  Saved read_saved(io::ArchiveReader& r) const;
  // Adopts a record read_saved (or snapshot) gave. The calendar must then be rebuilt from
  // the event records (EventLoopBase::resume).
  void restore(Saved&& s) noexcept;
  // The record restore takes, copied in memory (into `s`'s buffers, kept between calls):
  // the parallel loop's way back to the start of a run it must do again.
  void snapshot(Saved& s) const;

private:
  bool take_out(int i);  // remove_disk without the counting; false when the slot was empty
  void grow();
  void add_books(int i, double sign);
  void note_body(const DiskBody& b);  // updates uniform_radius / uniform_mass

  double now_ = 0.0;
  double epoch_ = 0.0;      // the disk records' common epoch (Disk)
  double uniform_r_ = -1.0;  // uniform_radius()
  double uniform_m_ = -1.0;  // uniform_mass()
  double kin_ = 0.0, rot_ = 0.0, px_ = 0.0, py_ = 0.0, mtot_ = 0.0;
  double kxx_ = 0.0, kxy_ = 0.0, kyy_ = 0.0;  // kinetic_tensor()
  int n_present_ = 0, n_frozen_ = 0;
  double dmin_ = 0.0, dmax_ = kNever;
  std::int64_t next_tag_ = 1;  // the id the next disk added gets
  std::uint64_t next_rebase_ = 0;  // stats.events at which maybe_rebase rebases
  std::vector<int> touched_, free_, added_;
  std::vector<int> rescheduled_;  // timers to ask again (reschedule)
  std::vector<Removal> removed_;
  bool grown_ = false;
  bool events_ready_ = false;  // the loop has started: event holds an entry per slot and timer
};

}  // namespace grainflow::ed
