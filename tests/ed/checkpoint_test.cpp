// Checkpoints of the ED engine (Simulation::save_state / load_state): a run saved at T1 and
// restored into a simulation constructed the same way must continue bit for bit — every
// disk, slot, counter, stat, the kinetic energy and the field sampler's frames equal to an
// uninterrupted run's at T2 — in an equilibrium box (both calendars), the dense open stream
// (dispenser piston + recharge + filter, obstacle, sampler), the thermostat (each kind, in
// the box and in the dense stream, saved mid-sample interval), the low-density stream
// (inlet/outlet), with disks churning in and out (slot arrays growing after T1), and with
// changes made from outside just before the save. Archives that do not fit are refused
// with a message naming why and leave the simulation as it was; saving is deterministic.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "engine/core/error.hpp"
#include "engine/core/rng.hpp"
#include "engine/ed/checkpoint.hpp"
#include "engine/ed/dense_stream.hpp"
#include "engine/ed/elastic_walls.hpp"
#include "engine/ed/field_sampler.hpp"
#include "engine/ed/low_density_stream.hpp"
#include "engine/ed/phase_timer.hpp"
#include "engine/ed/simulation.hpp"
#include "engine/ed/thermostat.hpp"
#include "tests/ed/churn.hpp"
#include "engine/io/archive.hpp"

namespace ed = grainflow::ed;
namespace io = grainflow::io;

namespace {

std::uint64_t bits(double v) {
  std::uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

// Pointers into a simulation built by a scenario (owned by it).
struct Handles {
  ed::FieldSampler* sampler = nullptr;
  ed::CircularObstacle* obstacle = nullptr;
  ed::DenseStream dense;
  ed::LowDensityStream low;
  ed::Thermostat* thermostat = nullptr;
};
using Builder = std::function<std::unique_ptr<ed::Simulation>(Handles&)>;

ed::SamplerConfig sampler_config(double lx, double ly, int nx, int ny, double interval, double exposure) {
  ed::SamplerConfig sc;
  sc.grid.nx = nx;
  sc.grid.ny = ny;
  sc.grid.lo = {0.0, 0.0};
  sc.grid.hi = {lx, ly};
  sc.interval = interval;
  sc.exposure = exposure;
  return sc;
}

std::string save(const ed::Simulation& sim) {
  io::ArchiveWriter w;
  sim.save_state(w);
  return w.take();
}

void load(ed::Simulation& sim, const std::string& bytes) {
  io::ArchiveReader r(bytes, "checkpoint");
  sim.load_state(r);
  EXPECT_TRUE(r.at_end());
}

// Everything observable, bit for bit. with_kT_integral: the time integral of kT is
// summed piecewise between run_until stops, so it matches only runs stopped at the same times.
void expect_same_run(const ed::Simulation& a, const ed::Simulation& b, bool with_kT_integral) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.count(), b.count());
  EXPECT_EQ(a.state().frozen_count(), b.state().frozen_count());
  EXPECT_EQ(bits(a.time()), bits(b.time()));
  const ed::Stats &x = a.stats(), &y = b.stats();
  EXPECT_EQ(x.events, y.events);
  EXPECT_EQ(x.collisions, y.collisions);
  EXPECT_EQ(x.sliding, y.sliding);
  EXPECT_EQ(x.cell_crossings, y.cell_crossings);
  EXPECT_EQ(x.stale, y.stale);
  EXPECT_EQ(x.agent_events, y.agent_events);
  EXPECT_EQ(x.timer_events, y.timer_events);
  EXPECT_EQ(x.inserted, y.inserted);
  EXPECT_EQ(x.removed, y.removed);
  EXPECT_EQ(x.removed_overlap, y.removed_overlap);
  EXPECT_EQ(x.tc_elastic, y.tc_elastic);
  // The TC model's state: restitution, cutoff, last-collision times, overlap log.
  EXPECT_EQ(bits(a.restitution()), bits(b.restitution()));
  EXPECT_EQ(bits(a.tau_tc()), bits(b.tau_tc()));
  EXPECT_EQ(bits(a.tau_tc_step()), bits(b.tau_tc_step()));
  EXPECT_EQ(a.state().last_collision.size(), b.state().last_collision.size());
  if (a.state().last_collision.size() == b.state().last_collision.size() && !a.state().last_collision.empty()) {
    EXPECT_EQ(std::memcmp(a.state().last_collision.data(), b.state().last_collision.data(),
                          a.state().last_collision.size() * sizeof(double)),
              0);
  }
  ASSERT_EQ(a.overlap_log().size(), b.overlap_log().size());
  for (std::size_t k = 0; k < a.overlap_log().size(); ++k)
    EXPECT_EQ(std::memcmp(&a.overlap_log()[k], &b.overlap_log()[k], sizeof(ed::OverlapRemoval)), 0) << "removal " << k;
  EXPECT_EQ(bits(x.t0), bits(y.t0));
  EXPECT_EQ(x.collisions0, y.collisions0);
  EXPECT_EQ(bits(x.virial), bits(y.virial));
  for (auto m : {&ed::Stats::virial_xx, &ed::Stats::virial_xy, &ed::Stats::virial_yy}) EXPECT_EQ(bits(x.*m), bits(y.*m));
  if (with_kT_integral) {
    EXPECT_EQ(bits(x.kT_integral), bits(y.kT_integral));
    for (auto m : {&ed::Stats::kinetic_integral_xx, &ed::Stats::kinetic_integral_xy, &ed::Stats::kinetic_integral_yy})
      EXPECT_EQ(bits(x.*m), bits(y.*m));
  }
  for (int k = 0; k < 3; ++k) EXPECT_EQ(bits(a.state().kinetic_tensor()[k]), bits(b.state().kinetic_tensor()[k]));
  EXPECT_EQ(bits(a.kinetic_energy()), bits(b.kinetic_energy()));
  EXPECT_EQ(bits(a.state().kinetic()), bits(b.state().kinetic()));
  EXPECT_EQ(bits(a.state().rotational()), bits(b.state().rotational()));
  EXPECT_EQ(bits(a.state().momentum().x()), bits(b.state().momentum().x()));
  EXPECT_EQ(bits(a.state().momentum().y()), bits(b.state().momentum().y()));
  // The persistent ids, and the one the next newcomer gets.
  EXPECT_EQ(a.state().next_tag(), b.state().next_tag());
  int slots_differ = 0, disks_differ = 0, counters_differ = 0, tags_differ = 0, first = -1;
  for (int i = 0; i < a.size(); ++i) {
    bool differ = false;
    if (a.state().slot[i] != b.state().slot[i]) ++slots_differ, differ = true;
    if (a.state().counter[i] != b.state().counter[i]) ++counters_differ, differ = true;
    if (a.present(i) && a.tag(i) != b.tag(i)) ++tags_differ, differ = true;
    // x, y, vx, vy (at the epoch) and r, m, w of the disks present (no padding in either).
    if (a.present(i) && (std::memcmp(&a.disks()[i], &b.disks()[i], sizeof(ed::Disk)) != 0 ||
                         std::memcmp(&a.bodies()[i], &b.bodies()[i], sizeof(ed::DiskBody)) != 0))
      ++disks_differ, differ = true;
    if (differ && first < 0) first = i;
  }
  EXPECT_EQ(slots_differ, 0) << "first slot that differs: " << first;
  EXPECT_EQ(disks_differ, 0) << "first slot that differs: " << first;
  EXPECT_EQ(counters_differ, 0) << "first slot that differs: " << first;
  EXPECT_EQ(tags_differ, 0) << "first slot that differs: " << first;
}

template <class T>
void expect_same_values(const std::vector<T>& a, const std::vector<T>& b) {
  ASSERT_EQ(a.size(), b.size());
  if (!a.empty()) {
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(T)), 0);
  }
}
void expect_same_field(const grainflow::core::ScalarField& a, const grainflow::core::ScalarField& b) {
  expect_same_values(a.values, b.values);  // NaN in masked bins: compared as bits too
  expect_same_values(a.mask, b.mask);
}
void expect_same_field(const grainflow::core::VectorField& a, const grainflow::core::VectorField& b) {
  ASSERT_EQ(a.values.size(), b.values.size());
  int differ = 0;
  for (std::size_t k = 0; k < a.values.size(); ++k)
    differ += bits(a.values[k].x()) != bits(b.values[k].x()) || bits(a.values[k].y()) != bits(b.values[k].y());
  EXPECT_EQ(differ, 0);
  expect_same_values(a.mask, b.mask);
}
template <class F>
void expect_same_optional(const std::optional<F>& a, const std::optional<F>& b) {
  ASSERT_EQ(a.has_value(), b.has_value());
  if (a) expect_same_field(*a, *b);
}
// The sampler's completed frames, taken from both (so the next take starts afresh).
void expect_same_frames(ed::FieldSampler& a, ed::FieldSampler& b) {
  const auto fa = a.take_frames(), fb = b.take_frames();
  ASSERT_EQ(fa.size(), fb.size());
  ASSERT_FALSE(fa.empty());
  for (std::size_t k = 0; k < fa.size(); ++k) {
    SCOPED_TRACE("frame " + std::to_string(k));
    EXPECT_EQ(bits(fa[k].t_begin), bits(fb[k].t_begin));
    EXPECT_EQ(bits(fa[k].t_end), bits(fb[k].t_end));
    EXPECT_EQ(fa[k].samples, fb[k].samples);
    expect_same_field(fa[k].fields.density, fb[k].fields.density);
    expect_same_optional(fa[k].fields.fraction, fb[k].fields.fraction);
    expect_same_optional(fa[k].fields.mean_velocity, fb[k].fields.mean_velocity);
    expect_same_optional(fa[k].fields.temperature, fb[k].fields.temperature);
    expect_same_optional(fa[k].fields.mean_speed, fb[k].fields.mean_speed);
    ASSERT_TRUE(fa[k].fields.mean_velocity.has_value());
  }
}

// A: uninterrupted to t2. B: to t1, saved, then on to t2. C: built the same way, run to
// c_first (if > 0) so that its state is not the fresh one, restored from B's archive, on to t2.
struct Restart {
  std::unique_ptr<ed::Simulation> a, b, c;
  Handles ha, hb, hc;
  std::string at_t1;  // B's archive
};

Restart restart(const Builder& build, double t1, double t2, double c_first = 0.0) {
  Restart r;
  r.a = build(r.ha);
  r.a->run_until(t2);
  r.b = build(r.hb);
  r.b->run_until(t1);
  r.at_t1 = save(*r.b);
  r.c = build(r.hc);
  if (c_first > 0.0) r.c->run_until(c_first);
  load(*r.c, r.at_t1);
  // Right after the restore: B's state, and save -> load -> save gives the same bytes.
  EXPECT_EQ(bits(r.c->time()), bits(t1));
  EXPECT_EQ(r.c->size(), r.b->size());
  EXPECT_TRUE(save(*r.c) == r.at_t1) << "save -> load -> save changed the bytes";
  r.b->run_until(t2);
  r.c->run_until(t2);
  return r;
}

// The checks every scenario shares.
void expect_restart_is_exact(Restart& r) {
  const ed::Stats& st = r.a->stats();
  std::printf("  to t2: %llu events, %llu collisions (%llu sliding), %llu agent and %llu timer events, %llu in, %llu out, "
              "%d slots, %d present, %d frozen, %zu frames, archive at t1 %zu bytes\n",
              (unsigned long long)st.events, (unsigned long long)st.collisions, (unsigned long long)st.sliding,
              (unsigned long long)st.agent_events, (unsigned long long)st.timer_events, (unsigned long long)st.inserted,
              (unsigned long long)st.removed, r.a->size(), r.a->count(), r.a->state().frozen_count(),
              r.ha.sampler ? r.ha.sampler->frames().size() : std::size_t(0), r.at_t1.size());
  {
    SCOPED_TRACE("uninterrupted A vs restored C");
    expect_same_run(*r.a, *r.c, false);
  }
  {
    SCOPED_TRACE("B (saved, continued) vs restored C");
    expect_same_run(*r.b, *r.c, true);
    // Everything the archive holds (agents' random streams and counters, free list, event
    // records, cell membership) agrees too.
    EXPECT_TRUE(save(*r.b) == save(*r.c)) << "the states at t2 differ somewhere";
  }
  if (r.ha.sampler) {
    SCOPED_TRACE("sampler frames A vs C");
    // B's frames equal C's as well (same archive bytes above); A's are the reference.
    expect_same_frames(*r.ha.sampler, *r.hc.sampler);
  }
}

// ---- 1. equilibrium periodic box ------------------------------------------------------
ed::Config box_config(ed::CalendarKind cal, double l = 30.0) {
  ed::Config c;
  c.lx = c.ly = l;
  c.area_fraction = 0.65;
  c.kT = 0.02;
  c.mu = 0.3;  // rough disks: spins and the sliding branch
  c.e = 1.0;
  c.e_t = 1.0;
  c.seed = 3;
  c.calendar = cal;
  return c;
}

Builder box_builder(ed::CalendarKind cal) {
  return [cal](Handles& h) {
    auto sim = std::make_unique<ed::Simulation>(box_config(cal));
    h.sampler = &sim->emplace_timer<ed::FieldSampler>(sampler_config(30.0, 30.0, 6, 6, 0.5, 10.0), sim->time());
    return sim;
  };
}

void check_box(ed::CalendarKind cal) {
  const double t1 = 23.3, t2 = 41.0;  // exposures end at 10, 20, 30, 40: t1 is mid-exposure
  Restart r = restart(box_builder(cal), t1, t2, 5.0);
  EXPECT_NE(std::fmod(t1, 10.0), 0.0);
  EXPECT_GT(r.a->stats().collisions, 10u * std::uint64_t(r.a->count()));
  EXPECT_GT(r.a->stats().sliding, 0u);
  expect_restart_is_exact(r);
}

}  // namespace

TEST(EdCheckpoint, EquilibriumBoxBucketCalendar) { check_box(ed::CalendarKind::bucket); }
TEST(EdCheckpoint, EquilibriumBoxCellHeapCalendar) { check_box(ed::CalendarKind::cell_heap); }

namespace {

// ---- 1b. inelastic box with the TC model (seed 003 ch. 5) --------------------------------
// Rough disks at e = 0.5, no cutoff at first and a step: at t ≈ 19.2 an inelastic collision
// comes below the clock's precision, removes its offender and raises τ_TC (the numbers are
// printed). Saved before that removal (t1 = 10) and after it (t1 = 23.3): the restored run
// continues bit for bit — last-collision times, cutoff, the log of removals included.
Builder tc_builder(ed::CalendarKind cal) {
  return [cal](Handles& h) {
    ed::Config c = box_config(cal);
    c.e = 0.5;
    c.tau_tc = 0.0;
    c.tau_tc_step = 1e-6;
    auto sim = std::make_unique<ed::Simulation>(c);
    h.sampler = &sim->emplace_timer<ed::FieldSampler>(sampler_config(30.0, 30.0, 6, 6, 0.5, 10.0), sim->time());
    return sim;
  };
}

void check_tc(ed::CalendarKind cal, double t1) {
  const double t2 = 41.0;
  Restart r = restart(tc_builder(cal), t1, t2, 5.0);
  ASSERT_GE(r.a->overlap_removals(), 1u);
  std::printf("  TC: %llu removal(s), the first at t = %.10g; tau_tc = %g; %llu TC-elastic collisions\n",
              (unsigned long long)r.a->overlap_removals(), r.a->overlap_log()[0].t, r.a->tau_tc(),
              (unsigned long long)r.a->stats().tc_elastic);
  EXPECT_GT(r.a->stats().tc_elastic, 0u);
  EXPECT_FALSE(r.a->state().last_collision.empty());
  if (t1 > 20.0) {
    EXPECT_LT(r.a->overlap_log()[0].t, t1);  // the archive holds a removal and a raised cutoff
  } else {
    EXPECT_GT(r.a->overlap_log()[0].t, t1);  // the restored run makes the same removal
  }
  expect_restart_is_exact(r);
}

}  // namespace

TEST(EdCheckpoint, InelasticTcBoxAfterARemovalBucketCalendar) { check_tc(ed::CalendarKind::bucket, 23.3); }
TEST(EdCheckpoint, InelasticTcBoxAfterARemovalCellHeapCalendar) { check_tc(ed::CalendarKind::cell_heap, 23.3); }
TEST(EdCheckpoint, InelasticTcBoxBeforeARemoval) { check_tc(ed::CalendarKind::bucket, 10.0); }

// Phased runs: elastic, then inelastic with the TC model from set_restitution and
// set_time_cutoff. The archive carries the restitution and cutoff as they stand, so a
// simulation constructed elastic, as the scene says, continues the inelastic phase.
TEST(EdCheckpoint, RestitutionChangedAtRunTimeIsRestored) {
  ed::Config c = box_config(ed::CalendarKind::bucket);
  c.mu = 0.0;
  ed::Simulation a(c), b(c);
  for (ed::Simulation* s : {&a, &b}) {
    s->run_until(5.0);
    s->set_restitution(0.6);
    s->set_time_cutoff(1e-3, 1e-4);
    s->run_until(10.0);
  }
  const std::string at10 = save(b);
  ed::Simulation restored(c);
  EXPECT_EQ(restored.restitution(), 1.0);
  load(restored, at10);
  EXPECT_EQ(restored.restitution(), 0.6);
  EXPECT_EQ(restored.tau_tc(), 1e-3);
  EXPECT_EQ(restored.tau_tc_step(), 1e-4);
  EXPECT_TRUE(restored.time_cutoff_on());
  a.run_until(20.0);
  restored.run_until(20.0);
  b.run_until(20.0);
  expect_same_run(a, restored, false);
  expect_same_run(b, restored, true);
  EXPECT_TRUE(save(b) == save(restored));
  EXPECT_LT(restored.state().kT(), 0.5 * c.kT);  // it did cool
}

namespace {

// ---- 2. dense open stream: dispenser piston + recharge + filter, obstacle, sampler --------
// cooled: inelastic disks (e = 0.9, TC model) and boundaries at the cooled stream's
// temperature (local_kT), whose running means the checkpoint must keep.
Builder dense_builder(ed::CalendarKind cal, bool cooled = false) {
  return [cal, cooled](Handles& h) {
    ed::Config c;
    c.lx = 60.0;
    c.ly = 16.0;
    c.area_fraction = 0.65;
    c.kT = 0.02;
    c.stream = {0.1, 0.0};
    c.periodic_x = false;
    c.open_x = true;
    c.mu = 0.2;  // dispensed disks draw a spin too
    c.seed = 11;
    c.calendar = cal;
    if (cooled) {
      c.e = 0.9;
      c.tau_tc = 1e-4;
      c.tau_tc_step = 1e-5;
    }
    auto sim = std::make_unique<ed::Simulation>(c);
    // The order of the scene runner: sampler, obstacle, stream boundaries.
    h.sampler = &sim->emplace_timer<ed::FieldSampler>(sampler_config(c.lx, c.ly, 12, 4, 1.0, 20.0), sim->time());
    ed::ObstacleConfig oc;
    oc.centre = {28.0, 8.0};
    oc.radius = 3.0;
    oc.boundary = ed::ObstacleBoundary::thermal;  // draws from its random stream
    oc.kT = c.kT;
    oc.seed = grainflow::core::substream_seed(c.seed, 1);
    h.obstacle = &sim->add_obstacle(oc);
    ed::DenseStreamConfig d;
    d.U = 0.1;
    d.kT = c.kT;
    d.area_fraction = 0.65;
    d.filter_distance = 3.0;
    d.piston = ed::PistonKind::thermal;
    d.local_kT = cooled;
    d.seed = grainflow::core::substream_seed(c.seed, 2);
    h.dense = ed::add_dense_stream(*sim, d);
    return sim;
  };
}

void check_dense(ed::CalendarKind cal, bool cooled = false) {
  // Recharges every strip / U = 10; exposures end at multiples of 20: t1 is mid-cycle and
  // mid-exposure.
  const double t1 = 83.7, t2 = 150.0;
  Restart r = restart(dense_builder(cal, cooled), t1, t2, 30.0);
  EXPECT_NE(std::fmod(t1, 20.0), 0.0);
  // Between t1 and t2 disks are inserted, frozen and removed (slots reused), the piston
  // recharges, the obstacle and filter draw random numbers. Reference: a run to t1.
  Handles h1;
  auto at_t1 = dense_builder(cal, cooled)(h1);
  at_t1->run_until(t1);
  const double pos = h1.dense.piston->position(t1);
  EXPECT_GT(pos, 0.0);
  EXPECT_LT(pos, h1.dense.piston->strip());
  EXPECT_GT(at_t1->stats().removed, 0u);  // free slots exist at t1
  EXPECT_GT(r.a->stats().inserted, at_t1->stats().inserted);
  EXPECT_GT(r.a->stats().removed, at_t1->stats().removed);
  EXPECT_GT(r.ha.dense.filter->frozen(), h1.dense.filter->frozen());
  // A cooled stream reaches the filter too cold for its back flux (F−/F+ ≈ 0).
  if (!cooled) {
    EXPECT_GT(r.ha.dense.filter->turned_back(), h1.dense.filter->turned_back());
  }
  EXPECT_GT(r.ha.dense.piston->cycles(), h1.dense.piston->cycles());
  EXPECT_GT(r.ha.obstacle->hits(), h1.obstacle->hits());
  expect_restart_is_exact(r);
  // The agents' own measurements agree.
  EXPECT_EQ(r.ha.obstacle->hits(), r.hc.obstacle->hits());
  EXPECT_EQ(bits(r.ha.obstacle->impulse().x()), bits(r.hc.obstacle->impulse().x()));
  EXPECT_EQ(bits(r.ha.obstacle->impulse().y()), bits(r.hc.obstacle->impulse().y()));
  EXPECT_EQ(r.ha.dense.piston->hits(), r.hc.dense.piston->hits());
  EXPECT_EQ(r.ha.dense.piston->cycles(), r.hc.dense.piston->cycles());
  EXPECT_EQ(bits(r.ha.dense.piston->impulse_x()), bits(r.hc.dense.piston->impulse_x()));
  EXPECT_EQ(r.ha.dense.filter->frozen(), r.hc.dense.filter->frozen());
  EXPECT_EQ(r.ha.dense.filter->turned_back(), r.hc.dense.filter->turned_back());
  EXPECT_EQ(bits(r.ha.dense.piston->kT()), bits(r.hc.dense.piston->kT()));
  EXPECT_EQ(bits(r.ha.dense.filter->kT()), bits(r.hc.dense.filter->kT()));
  if (cooled) {  // the boundaries follow the cooled stream, well below kT = 0.02
    std::printf("  kT at t1: dispenser %.3g filter %.3g; at t2: %.3g, %.3g\n", h1.dense.piston->kT(),
                h1.dense.filter->kT(), r.ha.dense.piston->kT(), r.ha.dense.filter->kT());
    for (double kT : {h1.dense.filter->kT(), h1.dense.piston->kT(), r.ha.dense.filter->kT(), r.ha.dense.piston->kT()})
      EXPECT_LT(kT, 0.005);
  }
}

}  // namespace

TEST(EdCheckpoint, DenseStreamWithObstacleBucketCalendar) { check_dense(ed::CalendarKind::bucket); }
TEST(EdCheckpoint, DenseStreamWithObstacleCellHeapCalendar) { check_dense(ed::CalendarKind::cell_heap); }
TEST(EdCheckpoint, CooledDenseStreamWithLocalTemperatureBoundaries) { check_dense(ed::CalendarKind::bucket, true); }

namespace {

// ---- 2b. the thermostat (seed 003 ch. 6): its random stream, next event, sample clock and
// averaged bins, in the box and in the dense stream (N changing, frozen disks to skip).
ed::ThermostatConfig thermostat_config(ed::ThermostatKind kind, double lx, double ly, std::uint64_t seed) {
  ed::ThermostatConfig t;
  t.kind = kind;
  t.kT = 0.03;
  t.tau = 2.0;
  t.tau_v = 4.0;
  t.sample_interval = 0.1;
  t.grid.nx = 6;
  t.grid.ny = 3;
  t.grid.lo = {0.0, 0.0};
  t.grid.hi = {lx, ly};
  t.seed = seed;
  return t;
}

Builder thermostat_builder(ed::ThermostatKind kind, bool dense) {
  return [kind, dense](Handles& h) {
    std::unique_ptr<ed::Simulation> sim =
        dense ? dense_builder(ed::CalendarKind::bucket)(h) : box_builder(ed::CalendarKind::bucket)(h);
    const ed::Config& c = sim->config();
    h.thermostat = &sim->emplace_timer<ed::Thermostat>(
        thermostat_config(kind, c.lx, c.ly, grainflow::core::substream_seed(c.seed, 3)), sim->state());
    return sim;
  };
}

void check_thermostat(ed::ThermostatKind kind, bool dense) {
  // Samples every 0.1 from 0: t1 = 23.33 / 83.73 lies between two.
  const double t1 = dense ? 83.73 : 23.33, t2 = dense ? 150.0 : 41.0;
  Restart r = restart(thermostat_builder(kind, dense), t1, t2, 7.0);
  Handles h1;
  auto at_t1 = thermostat_builder(kind, dense)(h1);
  at_t1->run_until(t1);
  EXPECT_GT(h1.thermostat->events(), 1000u);
  EXPECT_GT(r.ha.thermostat->events(), h1.thermostat->events() + 1000u);
  if (kind == ed::ThermostatKind::single) {
    EXPECT_GT(h1.thermostat->samples(), 200u);
  }
  expect_restart_is_exact(r);
  EXPECT_EQ(r.ha.thermostat->events(), r.hc.thermostat->events());
  EXPECT_EQ(r.ha.thermostat->samples(), r.hc.thermostat->samples());
  EXPECT_EQ(r.ha.thermostat->unpaired(), r.hc.thermostat->unpaired());
  EXPECT_EQ(bits(r.ha.thermostat->energy()), bits(r.hc.thermostat->energy()));
}

}  // namespace

TEST(EdCheckpoint, ThermostatSingleInTheBox) { check_thermostat(ed::ThermostatKind::single, false); }
TEST(EdCheckpoint, ThermostatDualInTheBox) { check_thermostat(ed::ThermostatKind::dual, false); }
TEST(EdCheckpoint, ThermostatGlobalInTheBox) { check_thermostat(ed::ThermostatKind::global, false); }
TEST(EdCheckpoint, ThermostatSingleInTheDenseStream) { check_thermostat(ed::ThermostatKind::single, true); }
TEST(EdCheckpoint, ThermostatDualInTheDenseStream) { check_thermostat(ed::ThermostatKind::dual, true); }

// ---- phased runs and moving walls --------------------------------------------------------
// Couette walls (thermal, moving), a flip obstacle, the thermostat, and three phases: at
// t = 10 inelastic (e, obstacle r, the thermal surface) with the thermostat off, at t = 30 the thermostat on at
// another T. Saved between the phases or before the first, continued across them.
namespace {

struct PhasedHandles {
  ed::PhaseTimer* phases = nullptr;
  ed::ElasticWalls* walls = nullptr;
};

Builder phased_builder(PhasedHandles* ph) {
  return [ph](Handles& h) {
    ed::Config c = box_config(ed::CalendarKind::bucket);
    c.area_fraction = 0.5;
    c.periodic_y = false;
    c.mu = 0.0;
    c.tau_tc = 1e-4;
    c.tau_tc_step = 1e-4;
    auto sim = std::make_unique<ed::Simulation>(c);
    h.sampler = &sim->emplace_timer<ed::FieldSampler>(sampler_config(30.0, 30.0, 6, 6, 0.5, 10.0), sim->time());
    ed::WallConfig wc;
    wc.surface = ed::WallSurface::thermal;
    wc.kT = 0.02;
    wc.u_low = -0.1;
    wc.u_high = 0.1;
    wc.seed = 17;
    sim->walls()->configure(wc);
    ed::ObstacleConfig oc;
    oc.centre = {15.0, 15.0};
    oc.radius = 3.0;
    oc.boundary = ed::ObstacleBoundary::flip;
    oc.seed = 5;
    h.obstacle = &sim->add_obstacle(oc);
    h.thermostat = &sim->emplace_timer<ed::Thermostat>(thermostat_config(ed::ThermostatKind::single, 30.0, 30.0, 9),
                                                       sim->state());
    ed::Simulation* s = sim.get();
    ed::CircularObstacle* o = h.obstacle;
    ed::Thermostat* th = h.thermostat;
    auto& timer = sim->emplace_timer<ed::PhaseTimer>(
        std::vector<double>{10.0, 30.0},
        [s, o, th](ed::SystemState& st, std::size_t k) {
          if (k == 0) {
            s->set_restitution(0.9);
            o->set_restitution(0.8);
            o->set_boundary(ed::ObstacleBoundary::thermal);  // the checkpoint keeps the surface
            th->set_active(false, st);
          } else {
            th->set_temperature(0.04);
            th->set_active(true, st);
          }
        },
        sim->time());
    if (ph) {
      ph->phases = &timer;
      ph->walls = sim->walls();
    }
    return sim;
  };
}

void check_phased(double t1) {
  const double t2 = 41.0;
  Restart r = restart(phased_builder(nullptr), t1, t2, 3.0);
  expect_restart_is_exact(r);
  EXPECT_EQ(bits(r.a->restitution()), bits(0.9));
  EXPECT_EQ(bits(r.hc.obstacle->config().restitution), bits(0.8));
  EXPECT_EQ(r.hc.obstacle->config().boundary, ed::ObstacleBoundary::thermal);
  EXPECT_TRUE(r.hc.thermostat->active());
  EXPECT_EQ(bits(r.hc.thermostat->config().kT), bits(0.04));
  EXPECT_EQ(r.ha.thermostat->events(), r.hc.thermostat->events());
  EXPECT_EQ(bits(r.ha.thermostat->energy()), bits(r.hc.thermostat->energy()));
  const ed::ElasticWalls *wa = r.a->walls(), *wc = r.c->walls();
  for (auto w : {ed::wall_y_low, ed::wall_y_high}) {
    EXPECT_GT(wa->hits(w), 100u);
    EXPECT_EQ(wa->hits(w), wc->hits(w));
    EXPECT_EQ(bits(wa->momentum_given(w).x()), bits(wc->momentum_given(w).x()));
    EXPECT_EQ(bits(wa->energy_given(w)), bits(wc->energy_given(w)));
  }
}

}  // namespace

TEST(EdCheckpoint, PhasedRunWithMovingWallsSavedBetweenPhases) { check_phased(23.3); }
TEST(EdCheckpoint, PhasedRunWithMovingWallsSavedBeforeTheFirstPhase) { check_phased(7.7); }

TEST(EdCheckpoint, RefusesAThermostatOfAnotherKindOrGrid) {
  Handles h;
  auto src = thermostat_builder(ed::ThermostatKind::single, false)(h);
  src->run_until(2.0);
  const std::string bytes = save(*src);
  for (auto [kind, nx, why] : {std::tuple{ed::ThermostatKind::dual, 6, "the thermostat is 'single' on 6 x 3 bins in "
                                                                        "the archive, 'dual' on 6 x 3 here"},
                               std::tuple{ed::ThermostatKind::single, 5, "'single' on 6 x 3 bins in the archive, "
                                                                         "'single' on 5 x 3 here"}}) {
    SCOPED_TRACE(why);
    Handles h2;
    auto sim = box_builder(ed::CalendarKind::bucket)(h2);
    ed::ThermostatConfig t = thermostat_config(kind, 30.0, 30.0, 1);
    t.grid.nx = nx;
    sim->emplace_timer<ed::Thermostat>(t, sim->state());
    io::ArchiveReader rd(bytes, "checkpoint box.ckpt");
    const std::string before = save(*sim);
    try {
      sim->load_state(rd);
      ADD_FAILURE() << "accepted";
    } catch (const grainflow::Error& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
    EXPECT_TRUE(save(*sim) == before);
  }
}

namespace {

// ---- 3. low-density stream: inlet + inlet plane + outlet, obstacle (flip), sampler --------
Builder low_builder() {
  return [](Handles& h) {
    ed::Config c;
    c.lx = 40.0;
    c.ly = 40.0;
    c.area_fraction = 0.04;
    c.kT = 0.02;
    c.stream = {0.1, 0.0};
    c.periodic_x = false;
    c.open_x = true;
    c.seed = 21;
    auto sim = std::make_unique<ed::Simulation>(c);
    h.sampler = &sim->emplace_timer<ed::FieldSampler>(sampler_config(c.lx, c.ly, 8, 4, 1.0, 20.0), sim->time());
    ed::ObstacleConfig oc;
    oc.centre = {20.0, 20.0};
    oc.radius = 2.0;
    oc.boundary = ed::ObstacleBoundary::flip;
    oc.seed = grainflow::core::substream_seed(c.seed, 1);
    h.obstacle = &sim->add_obstacle(oc);
    ed::LowDensityStreamConfig l;
    l.U = 0.1;
    l.kT = c.kT;
    l.number_density = 0.04 / (std::numbers::pi / 4.0);
    l.seed = grainflow::core::substream_seed(c.seed, 2);
    const double x_out = c.lx - 1.0;
    sim->remove_disks_unless([&](int i) { return sim->disks()[i].x >= l.x_in && sim->disks()[i].x <= x_out; });
    h.low = ed::add_low_density_stream(*sim, l);
    return sim;
  };
}

}  // namespace

TEST(EdCheckpoint, LowDensityStreamInletOutlet) {
  const double t1 = 97.3, t2 = 260.0;
  Restart r = restart(low_builder(), t1, t2, 12.0);
  Handles h1;
  auto at_t1 = low_builder()(h1);
  at_t1->run_until(t1);
  EXPECT_GT(r.ha.low.inlet->injected(), h1.low.inlet->injected());
  EXPECT_GT(r.ha.low.outlet->removed(), h1.low.outlet->removed());
  EXPECT_GT(r.ha.low.outlet->turned_back(), h1.low.outlet->turned_back());
  EXPECT_GT(r.ha.low.inlet_plane->removed() + r.ha.obstacle->hits(), h1.low.inlet_plane->removed() + h1.obstacle->hits());
  EXPECT_GT(at_t1->stats().removed, 0u);
  expect_restart_is_exact(r);
  EXPECT_EQ(r.ha.low.inlet->arrivals(), r.hc.low.inlet->arrivals());
  EXPECT_EQ(r.ha.low.inlet->injected(), r.hc.low.inlet->injected());
  EXPECT_EQ(r.ha.low.inlet->blocked_tries(), r.hc.low.inlet->blocked_tries());
  EXPECT_EQ(r.ha.low.outlet->arrivals(), r.hc.low.outlet->arrivals());
  EXPECT_EQ(r.ha.low.outlet->removed(), r.hc.low.outlet->removed());
  EXPECT_EQ(r.ha.low.inlet_plane->removed(), r.hc.low.inlet_plane->removed());
}

namespace {

// ---- 4. churn: disks removed, added (slot arrays growing after t1) and frozen -----------
// A timer that, every dt, removes a random disk, adds one or two at random free places
// and now and then freezes one, from its own random stream (saved with it).
class Churn final : public ed::TimerAgent {
public:
  explicit Churn(double dt) : next_(dt), dt_(dt) {}
  std::string_view name() const override { return "churn"; }
  double event_time(const ed::SystemState&) const override { return next_; }
  void action(ed::SystemState& s) override {
    ++actions_;
    next_ += dt_;
    ed::test::churn(s, rng_, actions_, 2);  // more in than out: the arrays must grow
  }
  // Its clock, count and random stream.
  void save(io::ArchiveWriter& w) const override {
    w.pod(next_);
    w.pod(actions_);
    w.rng(rng_);
  }
  void load(io::ArchiveReader& r) override {
    r.pod(next_);
    r.pod(actions_);
    r.rng(rng_);
  }

private:
  double next_, dt_;
  std::int64_t actions_ = 0;
  grainflow::core::Rng rng_{99};
};

Builder churn_builder(ed::CalendarKind cal) {
  return [cal](Handles&) {
    ed::Config c;
    c.lx = 16.0;
    c.ly = 16.0;
    c.area_fraction = 0.1;
    c.kT = 1.0;
    c.seed = 5;
    c.calendar = cal;
    auto sim = std::make_unique<ed::Simulation>(c);
    sim->emplace_timer<Churn>(0.05);
    return sim;
  };
}

void check_churn(ed::CalendarKind cal) {
  const double t1 = 1.23, t2 = 4.5;
  Restart r = restart(churn_builder(cal), t1, t2);
  Handles h;
  auto fresh = churn_builder(cal)(h);
  // B grew its slot arrays before t1 and again after: the restored C took the grown size.
  EXPECT_GT(r.b->size(), fresh->size());
  Handles h1;
  auto at_t1 = churn_builder(cal)(h1);
  at_t1->run_until(t1);
  EXPECT_GT(at_t1->size(), fresh->size());
  EXPECT_GT(r.a->size(), at_t1->size());
  EXPECT_GT(r.a->state().frozen_count(), 0);
  expect_restart_is_exact(r);
}

}  // namespace

TEST(EdCheckpoint, ChurningDisksGrowTheSlotsBucketCalendar) { check_churn(ed::CalendarKind::bucket); }
TEST(EdCheckpoint, ChurningDisksGrowTheSlotsCellHeapCalendar) { check_churn(ed::CalendarKind::cell_heap); }

// ---- 5. changes made from outside just before the save ----------------------------------
// set_velocity, remove_disk, add_disk and freeze between runs are settled by the loop when
// the next run starts; saved unsettled, they must be settled the same way after the restore.
TEST(EdCheckpoint, UnsettledOutsideChangesAreKept) {
  const double t1 = 6.5, t2 = 20.0;
  auto outside = [](ed::Simulation& sim) {
    ed::SystemState& s = sim.state();
    s.set_velocity(3, 0.1, -0.05);
    s.remove_disk(10);
    s.freeze(20, 0.05, 0.0);
    // A new disk where disk 10 was (it left now, so the place is free).
    ed::DiskInit d;
    const grainflow::Vec2 p = s.position_now(10);
    d.r = {p.x() - s.grid.lx() * std::floor(p.x() / s.grid.lx()), p.y() - s.grid.ly() * std::floor(p.y() / s.grid.ly())};
    d.v = {0.0, 0.1};
    d.radius = 0.5;
    d.mass = 1.0;
    s.add_disk(d);
  };
  for (auto cal : {ed::CalendarKind::bucket, ed::CalendarKind::cell_heap}) {
    SCOPED_TRACE(ed::calendar_name(cal));
    Handles ha, hc;
    auto a = box_builder(cal)(ha);
    a->run_until(t1);
    outside(*a);
    const std::string bytes = save(*a);
    auto c = box_builder(cal)(hc);
    load(*c, bytes);
    a->run_until(t2);
    c->run_until(t2);
    expect_same_run(*a, *c, true);
    EXPECT_TRUE(save(*a) == save(*c));
    expect_same_frames(*ha.sampler, *hc.sampler);
  }
}

// ---- 6. refusals ------------------------------------------------------------------------
namespace {

std::string error_of(ed::Simulation& sim, std::string_view bytes) {
  io::ArchiveReader r(bytes, "checkpoint box.ckpt");
  try {
    sim.load_state(r);
  } catch (const grainflow::Error& e) {
    return e.what();
  }
  return "(accepted)";
}

// Refused, with `why` in the message, and the simulation left exactly as it was.
void expect_refused(ed::Simulation& sim, std::string_view bytes, const std::string& why) {
  const std::string before = save(sim);
  const std::string msg = error_of(sim, bytes);
  EXPECT_NE(msg.find(why), std::string::npos) << msg;
  EXPECT_NE(msg.find("checkpoint box.ckpt"), std::string::npos) << msg;
  EXPECT_TRUE(save(sim) == before) << "a refused archive changed the simulation: " << msg;
}

}  // namespace

TEST(EdCheckpoint, RefusesArchivesThatDoNotFit) {
  Handles h;
  auto src = box_builder(ed::CalendarKind::bucket)(h);
  src->run_until(3.0);
  const std::string bytes = save(*src);
  {
    SCOPED_TRACE("another N");
    ed::Config c = box_config(ed::CalendarKind::bucket);
    c.area_fraction = 0.6;
    ed::Simulation sim(c);
    sim.emplace_timer<ed::FieldSampler>(sampler_config(30.0, 30.0, 6, 6, 0.5, 10.0), 0.0);
    expect_refused(sim, bytes, "built with 745 disks, this one with 688");
  }
  {
    SCOPED_TRACE("another box");
    ed::Config c = box_config(ed::CalendarKind::bucket, 31.0);
    c.n = 745;
    ed::Simulation sim(c);
    sim.emplace_timer<ed::FieldSampler>(sampler_config(30.0, 30.0, 6, 6, 0.5, 10.0), 0.0);
    expect_refused(sim, bytes, "the box is 30 x 30 (x periodic, y periodic) in the archive, 31 x 31");
  }
  {
    SCOPED_TRACE("another calendar");
    Handles h2;
    auto sim = box_builder(ed::CalendarKind::cell_heap)(h2);
    expect_refused(*sim, bytes, "the calendar is 'bucket' in the archive, 'cell_heap' here");
  }
  {
    SCOPED_TRACE("another collision rule");
    ed::Config c = box_config(ed::CalendarKind::bucket);
    c.mu = 0.0;
    ed::Simulation sim(c);
    sim.emplace_timer<ed::FieldSampler>(sampler_config(30.0, 30.0, 6, 6, 0.5, 10.0), 0.0);
    expect_refused(sim, bytes, "collision rule");
  }
  {
    SCOPED_TRACE("an extra agent");
    Handles h2;
    auto sim = box_builder(ed::CalendarKind::bucket)(h2);
    sim->add_agent(std::make_unique<ed::ElasticWalls>(30.0, 30.0, false, false));
    expect_refused(*sim, bytes, "the agents are [] in the archive, [walls] here");
  }
  {
    SCOPED_TRACE("a missing timer");
    ed::Simulation sim(box_config(ed::CalendarKind::bucket));
    expect_refused(sim, bytes, "the timers are [sampler] in the archive, [] here");
  }
  {
    SCOPED_TRACE("a sampler on other bins (found after the header)");
    ed::Simulation sim(box_config(ed::CalendarKind::bucket));
    sim.emplace_timer<ed::FieldSampler>(sampler_config(30.0, 30.0, 5, 6, 0.5, 10.0), 0.0);
    sim.run_until(2.0);
    expect_refused(sim, bytes, "samples per exposure on 6 x 6 bins in the archive, 20 on 5 x 6 here");
  }
  {
    SCOPED_TRACE("truncated: the first half");
    Handles h2;
    auto sim = box_builder(ed::CalendarKind::bucket)(h2);
    sim->run_until(1.0);  // its agents have state of their own, to be put back
    expect_refused(*sim, std::string_view(bytes).substr(0, bytes.size() / 2), "is truncated");
  }
  {
    SCOPED_TRACE("truncated: all but the last byte");
    Handles h2;
    auto sim = box_builder(ed::CalendarKind::bucket)(h2);
    sim->run_until(1.0);
    expect_refused(*sim, std::string_view(bytes).substr(0, bytes.size() - 1), "is truncated");
  }
  {
    SCOPED_TRACE("corrupt: a disk listed in the wrong cell");
    // The last array is the disks' places in their cells (int32 each): bump the last one.
    std::string bad = bytes;
    const std::size_t at = bad.size() - 4 - std::string("ed.end").size() - 8;
    std::int32_t p;
    std::memcpy(&p, bad.data() + at, 4);
    p += 1;
    std::memcpy(bad.data() + at, &p, 4);
    Handles h2;
    auto sim = box_builder(ed::CalendarKind::bucket)(h2);
    expect_refused(*sim, bad, "is corrupt: disk 744 is not where the cell map says");
  }
  {
    SCOPED_TRACE("an archive of something else");
    Handles h2;
    auto sim = box_builder(ed::CalendarKind::bucket)(h2);
    io::ArchiveWriter w;
    w.tag("dem.config");
    expect_refused(*sim, w.bytes(), "expected section 'ed.simulation', found 'dem.config'");
  }
}

// ---- 7. determinism ---------------------------------------------------------------------
TEST(EdCheckpoint, SavingIsDeterministic) {
  Handles h1, h2, h3;
  auto a = dense_builder(ed::CalendarKind::bucket)(h1);
  auto b = dense_builder(ed::CalendarKind::bucket)(h2);
  a->run_until(41.5);
  b->run_until(41.5);
  const std::string s1 = save(*a);
  EXPECT_TRUE(save(*a) == s1) << "saving twice gave other bytes";
  // Two runs of the same construction: the same bytes (no padding or stale memory leaks in).
  EXPECT_TRUE(save(*b) == s1) << "two identical runs saved different bytes";
  // save -> load -> save.
  auto c = dense_builder(ed::CalendarKind::bucket)(h3);
  load(*c, s1);
  EXPECT_TRUE(save(*c) == s1);
  // Loading the same archive twice, or over itself, changes nothing.
  load(*c, s1);
  EXPECT_TRUE(save(*c) == s1);
  load(*a, s1);
  EXPECT_TRUE(save(*a) == s1);
  // Saving does not disturb the run: a saved-and-continued run equals one never saved.
  a->run_until(60.0);
  b->run_until(60.0);
  expect_same_run(*a, *b, true);
  EXPECT_GT(s1.size(), 64u * std::size_t(a->count()));
}
