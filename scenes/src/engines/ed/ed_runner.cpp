// `grainflow run` adapter of the 2D event-driven engine (engine/ed): its keys (ed_keys.hpp)
// → ed::Config, frames of disks coloured by the attributes of kDiskAttributes, stats rows
// from the engine's measurement window (seed 003 §4.1), and the engine's table row.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <numbers>
#include <optional>
#include <type_traits>
#include <cstdio>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "engine/core/error.hpp"
#include "engine/core/state_digest.hpp"
#include "engine/ed/field_sampler.hpp"
#include "engine/ed/simulation.hpp"
#include "engine/core/rng.hpp"
#include "engine/io/archive.hpp"
#include "engine/io/particle_reader.hpp"
#include "scenes/src/engines/ed/ed_agents.hpp"
#include "scenes/src/engines/ed/ed_keys.hpp"
#include "scenes/src/engines/colour_attributes.hpp"
#include "scenes/src/engines/engine_runner.hpp"
#include "scenes/src/engines/engine_table.hpp"
#include "scenes/src/engines/field_snapshot.hpp"
#include "scenes/src/engines/initial_file.hpp"
#include "scenes/src/engines/sampling.hpp"
#include "scenes/src/scene/run_keys.hpp"
#include "scenes/src/scene/scene.hpp"

namespace grainflow::scenes {
namespace {

namespace keys = ed_keys;

ed::Config ed_config(const Scene& sc) {
  ed::Config c;
  const auto box = sc.get(keys::box);
  c.lx = box[0];
  c.ly = box[1];
  if (auto eta = sc.find(keys::area_fraction)) {
    c.area_fraction = *eta;
    c.n = 0;
  } else if (auto n = sc.find(keys::n)) {
    c.n = int(std::lround(*n * c.lx * c.ly));
  } else if (sc.has(keys::N)) {
    c.n = int(sc.get(keys::N));
  }  // else: the disks come from system.initial.file
  c.kT = sc.get(keys::kT);
  c.stream = {sc.get(keys::U), 0.0};
  c.seed = std::uint64_t(sc.get(run_keys::seed));
  const auto periodic = sc.get(keys::periodic);
  c.periodic_x = periodic[0];
  c.periodic_y = periodic[1];
  c.e = sc.get(keys::e);
  c.mu = sc.get(keys::mu);
  const double e_t = sc.get(keys::e_t);
  c.e_t = c.mu > 0 ? e_t : 1.0;  // tangential restitution matters only with friction
  c.tau_tc = sc.get(keys::tau_tc);
  c.tau_tc_step = sc.get(keys::tau_tc_step);
  c.min_cell_size = sc.get(keys::cell_size);
  c.calendar = ed::calendar_from_name(sc.get(keys::calendar));
  c.lanes = int(sc.get(keys::lanes));
  c.threads = c.lanes == 2 ? ed::lane_threads() : 1;
  // Open stream boundaries close the x axis themselves (seed 003 §3.2–3.3): no x walls.
  c.open_x = sc.get(keys::stream_kind) != "periodic";
  return c;
}

// system.initial.kind = "file": the disks of one frame of system.initial.file (a run's
// particles.xyz, an XYZ or LAMMPS dump), so that e.g. cooling starts from an equilibrated
// fluid rather than from the lattice (seed 003 ch. 5). Velocities missing from the file are
// drawn at system.kT plus U from the run's own stream.
std::vector<ed::DiskInit> disks_from_file(const Scene& sc, const ed::Config& c) {
  const initial_file::InitialParticles f = initial_file::read(sc, 2, Vec3::Zero(), Vec3(c.lx, c.ly, 0.0));
  const int types = f.type.empty() ? 1 : *std::max_element(f.type.begin(), f.type.end());
  if (types > 1 || (!f.type.empty() && *std::min_element(f.type.begin(), f.type.end()) != 1))
    throw Error(f.what + ": the file has particle types 1.." + std::to_string(types) +
                ", but the ED engine has one kind of disk (radius and mass per disk); list \"type\" in "
                "system.initial.ignore to read them all as one kind");
  core::Rng rng(core::substream_seed(c.seed, 3));
  const double sd = std::sqrt(c.kT);
  std::vector<ed::DiskInit> disks(f.size());
  for (std::size_t i = 0; i < f.size(); ++i) {
    ed::DiskInit& d = disks[i];
    d.r = Vec2(f.position[i].x(), f.position[i].y());
    if (!f.radius.empty()) d.radius = f.radius[i];
    if (!f.density.empty()) d.mass = f.density[i] * std::numbers::pi * d.radius * d.radius;  // LAMMPS 2d: per area
    if (!f.mass.empty()) d.mass = f.mass[i];
    if (!f.velocity.empty()) {
      d.v = Vec2(f.velocity[i].x(), f.velocity[i].y());
    } else {
      const double s = sd / std::sqrt(d.mass);
      d.v = Vec2(rng.normal(0.0, s), rng.normal(0.0, s)) + c.stream;
    }
    if (!f.omega.empty()) d.omega = f.omega[i].z();
  }
  return disks;
}

std::unique_ptr<ed::Simulation> make_simulation(const Scene& sc) {
  ed::Config c = ed_config(sc);
  if (sc.get(keys::initial_kind) != "file") return std::make_unique<ed::Simulation>(c);
  std::vector<ed::DiskInit> disks = disks_from_file(sc, c);
  for (const auto* key : {&keys::area_fraction.path, &keys::n.path, &keys::N.path})
    if (sc.has(*key))
      std::fprintf(stderr, "grainflow: note: %.*s is not used: the disks come from system.initial.file (%zu disks)\n",
                   int(key->size()), key->data(), disks.size());
  c.n = int(disks.size());  // what the stream boundaries take as the density they feed
  try {
    return std::make_unique<ed::Simulation>(c, std::move(disks));
  } catch (const Error& e) {
    throw Error("system.initial.file = \"" + sc.get(initial_file::file) + "\": " + e.what());
  }
}

// What render.color_by may colour a disk by: the one list the schema offers and the
// snapshot computes (seed 003 draws speed; spin needs mu > 0 to be non-zero).
struct DiskAttribute {
  std::string_view name;
  double (*value)(const ed::Simulation& sim, std::size_t slot, const ed::Disk& d);
};
constexpr DiskAttribute kDiskAttributes[] = {
    {"uniform", nullptr},
    {"speed", [](const ed::Simulation&, std::size_t, const ed::Disk& d) { return std::hypot(d.vx, d.vy); }},
    {"vx", [](const ed::Simulation&, std::size_t, const ed::Disk& d) { return d.vx; }},
    {"vy", [](const ed::Simulation&, std::size_t, const ed::Disk& d) { return d.vy; }},
    {"spin", [](const ed::Simulation& sim, std::size_t i, const ed::Disk&) { return sim.omega(i); }},
    {"height", [](const ed::Simulation&, std::size_t, const ed::Disk& d) { return d.y; }},
};

std::vector<std::string> disk_attribute_names() { return attribute_names<DiskAttribute>(kDiskAttributes); }
const DiskAttribute& disk_attribute(std::string_view name) { return find_attribute<DiskAttribute>(kDiskAttributes, name); }

class EdRunner final : public EngineRunner {
public:
  explicit EdRunner(const Scene& sc)
      : sim_ptr_(make_simulation(sc)), sim_(*sim_ptr_), guard_(std::uint64_t(sc.get(keys::collapse_events))) {
    const ed::Config& cfg = sim_.config();
    if (cfg.e < 1.0 && cfg.tau_tc == 0.0 && cfg.tau_tc_step == 0.0)
      std::fprintf(stderr,
                   "grainflow: system.e = %g < 1 without the TC model (system.tau_tc = 0, system.tau_tc_step = 0): a "
                   "dense inelastic system collapses, and the run then fails; system.tau_tc ≈ 1e-4 of the mean free "
                   "time prevents it\n",
                   cfg.e);
    ed::SamplerConfig sc_cfg;
    const auto bins = sc.find(sample_keys::bins).value_or(sample_keys::kDefaultBins);
    sc_cfg.grid.nx = bins[0];
    sc_cfg.grid.ny = bins[1];
    sc_cfg.grid.lo = Vec2(0, 0);
    sc_cfg.grid.hi = Vec2(sim_.config().lx, sim_.config().ly);
    sc_cfg.exposure = sc.get(sample_keys::exposure);
    sc_cfg.interval = sample_keys::sample_interval(sc_cfg.exposure);
    sampler_ = &sim_.emplace_timer<ed::FieldSampler>(sc_cfg, sim_.time());
    for (const auto& agent : ed_agents())
      if (auto run = agent.attach(sc, sim_)) agents_.push_back(std::move(run));
  }

  double time() const override { return sim_.time(); }
  // 5·10^5 events ≈ 0.2–0.6 s at this engine's rates. Then the TC model's removals are
  // reported and the collapse guard consulted (it throws when the clock has stalled).
  void advance_to(double t) override {
    sim_.run_until(t, 500'000);
    after_advance();
  }
  void advance_steps(std::uint64_t n) override {
    sim_.advance(n);
    after_advance();
  }
  std::uint64_t steps_done() const override { return sim_.stats().events; }

  void snapshot(const std::string& colour_by, render::Snapshot& s) override {
    sim_.synchronise();
    const auto& cfg = sim_.config();
    s.dim = 2;
    s.lo = {0, 0, 0};
    s.hi = {cfg.lx, cfg.ly, 0};
    s.periodic = {cfg.periodic_x, cfg.periodic_y, false};
    s.time = sim_.time();
    s.length_unit = "σ";
    s.time_unit = "τ";
    const auto& disks = sim_.disks();
    // Slots of disks that left an open stream are empty: only present disks are drawn.
    const std::size_t count = std::size_t(sim_.count());
    s.pos_radius.resize(count * 4);
    s.attribute.clear();
    s.attribute_categorical = false;
    s.attribute_name = colour_by;
    const DiskAttribute& attribute = disk_attribute(colour_by);
    if (attribute.value) s.attribute.resize(count);
    std::size_t k = 0;
    for (std::size_t i = 0; i < disks.size(); ++i) {
      if (!sim_.present(int(i))) continue;
      const auto& d = disks[i];
      const std::size_t out = k++;
      float* p = &s.pos_radius[4 * out];
      p[0] = float(d.x);
      p[1] = float(d.y);
      p[2] = 0.0f;
      p[3] = float(sim_.bodies()[i].r);
      if (attribute.value) s.attribute[out] = float(attribute.value(sim_, i, d));
    }
    s.obstacles.clear();
    s.boundary_lines.clear();
    s.labels.clear();
    for (const auto& a : agents_) {
      a->draw(s);
      a->labels(s.labels);
    }
    // The exposure that ended most recently; none yet at the first frame.
    auto exposures = sampler_->take_frames();
    if (!exposures.empty()) {
      const ed::ExposureFields& e = exposures.back();
      // Reduced units (σ = m = 1, seed 003; time in τ, the unit of run.until): speeds in σ/τ,
      // rates in 1/τ; kT is an energy in the same units, named by itself.
      set_binned_fields(std::move(exposures.back().fields), s, {"σ⁻²", "", "σ/τ", "1/τ", "kT"},
                        render::FieldExposure{e.t_begin, e.t_end, e.samples, {0, 1}, std::nullopt});
      mask_solid_bins(s);
    }
    s.fields_pending = s.fields.empty() ? fmt::format("fields from t = {:g} τ (first exposure)", sampler_->exposure_end())
                                        : std::string();
    if (cfg.stream.x() != 0 || cfg.stream.y() != 0) s.reference_velocity = Eigen::Vector2d(cfg.stream.x(), cfg.stream.y());
  }

  void particles(core::ParticleFrame& f) const override {
    const auto& cfg = sim_.config();
    f.clear();
    f.dim = 2;
    f.time = sim_.time();
    f.has_box = true;
    f.box_lo = {0, 0, 0};
    f.box_hi = {cfg.lx, cfg.ly, 0};
    f.periodic = {cfg.periodic_x, cfg.periodic_y, false};
    std::vector<double> omega, mass;
    const auto& disks = sim_.disks();
    for (int i = 0; i < sim_.size(); ++i) {
      if (!sim_.present(i)) continue;
      const ed::Disk& d = disks[i];
      // The disk's persistent id, not its slot: an open stream gives a slot a disk left to
      // a newcomer, which gets an id of its own (ed::SystemState::tag).
      f.id.push_back(sim_.tag(i));
      f.type.push_back(1);
      f.position.emplace_back(d.x, d.y, 0.0);
      const ed::DiskBody& b = sim_.bodies()[i];
      f.radius.push_back(b.r);
      f.velocity.emplace_back(d.vx, d.vy, 0.0);
      omega.push_back(b.w);
      mass.push_back(b.m);
    }
    // The spin is ω_z: the vector (0, 0, ω), as OVITO's Angular Velocity and LAMMPS's
    // omegax omegay omegaz of a 2D run.
    const std::size_t n = omega.size();
    f.extra.emplace_back("omegax", std::vector<double>(n, 0.0));
    f.extra.emplace_back("omegay", std::vector<double>(n, 0.0));
    f.extra.emplace_back("omegaz", std::move(omega));
    f.extra.emplace_back("mass", std::move(mass));
  }

  // The engine's window, then each attached agent's columns (the obstacle's drag), then the
  // open-stream counters. The stats window: from the previous row to this one.
  std::vector<StatsColumn> stats_columns() const override {
    std::vector<StatsColumn> c = {
        {"collisions", "1", "disk–disk collisions since the start of the run (cumulative)"},
        {"events", "1", "calendar events processed since the start (collisions, cell crossings, walls, agents, stale)"},
        {"N", "1", "disks in the box now (frozen ones beyond an outlet filter included)"},
        {"kinetic_energy", "E", "Σ m|v|²/2 + Σ I ω²/2 over the disks now (translation and rotation, lab frame)"},
        {"kT", "E",
         "granular temperature averaged over the stats window: time average of Σ m|v − V|²/(2 N_mobile), V the "
         "mass-averaged velocity (seed 003 Eq. 4.9, i = 2)"},
        {"pressure", "E/σ²",
         "collision-virial pressure over the stats window: [N_mobile <kT> + Σ_coll r_ij·Δp_i / (2 t)] / A, A = the "
         "box area Lx·Ly (obstacle included), t the window length (Alder & Wainwright 1960)"},
        {"P_xx", "E/σ²",
         "pressure tensor xx over the stats window: [<Σ m (v_x − V_x)²> + Σ_coll r_ij,x Δp_i,x / t] / A (the disks, V "
         "and A of kT and pressure; (P_xx + P_yy)/2 = pressure)"},
        {"P_xy", "E/σ²",
         "pressure tensor xy over the stats window: [<Σ m (v_x − V_x)(v_y − V_y)> + Σ_coll (r_x Δp_y + r_y Δp_x) / (2 "
         "t)] / A (symmetrised; for a Couette flow along x between walls normal to y, −P_xy is the shear stress)"},
        {"P_yy", "E/σ²", "pressure tensor yy over the stats window: [<Σ m (v_y − V_y)²> + Σ_coll r_ij,y Δp_i,y / t] / A"},
        {"mean_free_time", "τ", "mean time between two collisions of one disk over the window: t N_mobile / (2 C)"},
        {"momentum_x", "m σ/τ", "Σ m v_x over the disks now"},
        {"momentum_y", "m σ/τ", "Σ m v_y over the disks now"}};
    for (const auto& a : agents_)
      for (auto& col : a->stats_columns()) c.push_back(std::move(col));
    c.push_back({"inserted", "1", "disks that entered through an open stream inlet since the start (cumulative)"});
    c.push_back({"removed", "1", "disks that left through an open stream outlet since the start (cumulative)"});
    c.push_back({"N_frozen", "1", "of N, the disks frozen beyond the outlet filter now (seed 003 §3.3)"});
    // The TC model (seed 003 ch. 5): disks removed as overlapping so far, the cutoff now.
    c.push_back({"removed_overlap", "1",
                 "disks removed as numerically overlapping by the TC model since the start (cumulative)"});
    c.push_back({"tau_tc", "τ", "the TC model's time cutoff now (raised by system.tau_tc_step at each removal)"});
    return c;
  }
  void check_finite() const override { require_finite(sim_.kinetic_energy()); }

  std::vector<double> stats_row() override {
    const ed::Observables o = sim_.observables();
    sim_.synchronise();
    const Vec2 p = sim_.momentum();
    const double kinetic = sim_.kinetic_energy();
    require_finite(kinetic);
    std::vector<double> row = {double(sim_.stats().collisions), double(sim_.stats().events), double(sim_.count()),
                               kinetic, o.kT, o.pressure, o.pressure_xx, o.pressure_xy, o.pressure_yy, o.mean_free_time, p.x(), p.y()};
    for (const auto& a : agents_) a->stats_row(o.duration, row);
    // N: disks present; inserted/removed: disks that entered/left through open stream
    // boundaries since the start; N_frozen: of N, those frozen by the filter (§3.3).
    for (double v : {double(sim_.stats().inserted), double(sim_.stats().removed), double(sim_.state().frozen_count())})
      row.push_back(v);
    row.push_back(double(sim_.overlap_removals()));
    row.push_back(sim_.tau_tc());
    if (first_mean_free_time_ == 0 && std::isfinite(o.mean_free_time) && o.mean_free_time > 0)
      first_mean_free_time_ = o.mean_free_time;
    sim_.reset_measurements();
    return row;
  }

  double work() const override { return double(sim_.stats().collisions); }
  std::string work_unit() const override { return "collisions"; }
  std::string advice() const override {
    const auto r = sim_.lane_runs();
    // A run done again goes at one thread's pace, after the two-thread try is thrown away.
    if (r.runs >= 8 && 4 * r.redone > r.runs)
      return fmt::format("{} of {} runs between stops were done again in the one-thread order (chains of collisions "
                         "across the cut, e.g. a dense inelastic cluster on it): two lanes gained little or lost; "
                         "system.lanes = 1 may be as fast", r.redone, r.runs);
    return {};
  }
  std::vector<std::pair<std::string, double>> figures() const override {
    std::vector<std::pair<std::string, double>> f;
    for (const auto& a : agents_) a->figures(f);
    f.insert(f.end(), {{"collisions", double(sim_.stats().collisions)},
                       {"events", double(sim_.stats().events)},
                       {"disks", double(sim_.count())},
                       {"disks_inserted", double(sim_.stats().inserted)},
                       {"disks_removed", double(sim_.stats().removed)},
                       {"disks_removed_overlap", double(sim_.overlap_removals())},
                       {"collisions_tc_elastic", double(sim_.stats().tc_elastic)},
                       {"tau_tc", sim_.tau_tc()},
                       {"area_fraction", sim_.area_fraction()},
                       {"lanes", double(sim_.config().lanes)},
                       {"threads", double(sim_.config().threads)}});
    if (sim_.config().lanes == 2) {
      // Runs between stops on two threads, and those a late event made it do again in the
      // merged order (ParallelLoop): many of them mean the second thread gains little.
      const auto r = sim_.lane_runs();
      f.insert(f.end(), {{"lane_runs", double(r.runs)}, {"lane_runs_redone", double(r.redone)}});
    }
    return f;
  }


  void save(io::ArchiveWriter& w) const override {
    sim_.save_state(w);  // the sampler's partial exposure and every agent's state included
    w.tag("ed.runner");
    w.pod(std::uint64_t(agents_.size()));
    for (const auto& a : agents_) a->save(w);
    // The collapse guard's window in progress, and the mean free time its message quotes.
    w.tag("ed.guard");
    w.pod(guard_.window_events());
    w.pod(guard_.window_time());
    w.pod(first_mean_free_time_);
  }
  void load(io::ArchiveReader& r) override {
    sim_.load_state(r);
    r.tag("ed.runner");
    if (r.get<std::uint64_t>() != agents_.size()) r.mismatch("another set of agents (obstacle, stream boundaries)");
    for (const auto& a : agents_) a->load(r);
    r.tag("ed.guard");
    const auto events0 = r.get<std::uint64_t>();
    const double t0 = r.get<double>();
    guard_.set_window_start(events0, t0);
    r.pod(first_mean_free_time_);
    reported_ = sim_.overlap_log().size();  // reported by the run before
  }

  std::string state_digest() const override {
    // Each present disk as stored (position at the common epoch, velocity, spin), in slot
    // order, with the clock and the epoch: equal for runs that made the same events in the
    // same order.
    core::StateDigest dg;
    dg.add(sim_.time());
    dg.add(sim_.state().epoch());
    const auto& disks = sim_.disks();
    for (int i = 0; i < sim_.size(); ++i) {
      if (!sim_.present(i)) continue;
      const ed::Disk& d = disks[i];
      dg.add(std::uint64_t(i));
      for (double v : {d.x, d.y, d.vx, d.vy, sim_.omega(i)}) dg.add(v);
    }
    return dg.hex();
  }

private:
  // Each overlap removal once, on stderr; then the collapse guard (a run whose clock has
  // stalled fails, with what to do, instead of spinning until it is killed).
  void after_advance() {
    const auto& log = sim_.overlap_log();
    for (; reported_ < log.size(); ++reported_) {
      const ed::OverlapRemoval& x = log[reported_];
      std::fprintf(stderr, "grainflow: t = %.9g: disk %lld at (%.6g, %.6g) overlapped and was removed; tau_tc → %.6g\n",
                   x.t, static_cast<long long>(x.id), x.x, x.y, x.tau_tc);
    }
    if (!guard_.collapsed(sim_)) return;
    const std::string rate = std::isfinite(guard_.rate())
                                 ? fmt::format("{:.3g} events per unit time, {:.3g} times the run's average",
                                               guard_.rate(), guard_.rate() / guard_.average_rate())
                                 : std::string("the clock did not move at all");
    const std::string suggestion =
        first_mean_free_time_ > 0 ? fmt::format(" (e.g. {:.2g}, 1e-4 of the mean free time {:.3g} of the first stats row)",
                                                1e-4 * first_mean_free_time_, first_mean_free_time_)
                                  : std::string(" (≈ 1e-4 of the mean free time)");
    std::string cure;
    if (sim_.time_cutoff_on())
      cure = fmt::format("raise system.tau_tc (now {:.3g}) or system.tau_tc_step (now {:.3g})", sim_.tau_tc(),
                         sim_.tau_tc_step());
    else if (sim_.restitution() < 1.0)
      cure = "switch on the TC model: system.tau_tc > 0" + suggestion + ", or system.tau_tc_step > 0";
    else
      cure = "check the scene (an elastic system should not stall)";
    throw Error(fmt::format("ed: the system collapsed at t = {:.9g}: the simulated time stopped advancing ({}; "
                            "e = {}: infinitely many collisions in a finite time, McNamara & Young 1994); allowed: "
                            "{}; or system.collapse_events = 0 to let it spin",
                            sim_.time(), rate, sim_.restitution(), cure));
  }

  // A state that has turned non-finite: see EngineRunner::check_finite.
  void require_finite(double kinetic) const {
    if (!std::isfinite(kinetic))
      throw Error(fmt::format("ed: the state is no longer finite at t = {:.6g}: kinetic energy = {}", sim_.time(),
                              kinetic));
  }

  // Bins an agent covers (inside the obstacle, beyond the outlet filter) hold no gas:
  // masked, not "empty" (seed 003 draws the obstacle over its fields). A bin it covers in
  // part holds its disks' centres in what is left open to them — outside the solid grown
  // by a disk radius —, so its number density and area fraction are divided by that open
  // fraction, not by the whole bin (else a false depletion ring is drawn around the
  // obstacle, exactly where compression is expected).
  void mask_solid_bins(render::Snapshot& s) {
    const auto& cfg = sim_.config();
    // Hard walls close a non-periodic axis (x only when no stream opens it): beyond them
    // is solid, so the bins along them are divided by their open part too.
    const bool wall_x = !cfg.periodic_x && !cfg.open_x, wall_y = !cfg.periodic_y;
    if (agents_.empty() && !wall_x && !wall_y) return;
    auto solid = [&](const Vec2& p) {
      if ((wall_x && (p.x() < 0 || p.x() > cfg.lx)) || (wall_y && (p.y() < 0 || p.y() > cfg.ly))) return true;
      for (const auto& a : agents_)
        if (a->solid(p)) return true;
      return false;
    };
    // The open fraction itself is a value everywhere (0 inside the solid), never masked.
    auto apply = [&](auto& field, bool per_area, bool is_open_field = false) {
      const std::vector<double>& open = open_fractions(field.grid, solid);
      for (std::size_t b = 0; b < open.size(); ++b) {
        if (is_open_field) {
          if constexpr (std::is_same_v<std::decay_t<decltype(field)>, core::ScalarField>) field.values[b] = open[b];
        } else if (centre_solid_[b]) {
          field.mask[b] = 0;
        } else if constexpr (std::is_same_v<std::decay_t<decltype(field)>, core::ScalarField>) {
          if (per_area && open[b] > 0.0 && open[b] < 1.0) field.values[b] /= open[b];
        }
      }
    };
    for (auto& f : s.fields) apply(f.field, f.name == "density" || f.name == "fraction", f.name == "open_fraction");
    if (s.velocity) apply(*s.velocity, false);
  }

  // The open fraction of every bin of grid g (8 × 8 points a bin), and whether its centre
  // is solid, computed once per grid:
  // the obstacle and the filter do not move.
  template <class Solid>
  const std::vector<double>& open_fractions(const core::GridGeometry& g, Solid&& solid) {
    if (open_grid_ && open_grid_->nx == g.nx && open_grid_->ny == g.ny && open_grid_->lo == g.lo &&
        open_grid_->hi == g.hi)
      return open_;
    constexpr int k = 8;
    // A centre closer than a disk radius (σ/2) to a solid is not possible: tested at the
    // point and 8 points around it.
    constexpr double r = 0.5;
    auto excluded = [&](const Vec2& p) {
      if (solid(p)) return true;
      for (int q = 0; q < 8; ++q) {
        const double a = q * std::numbers::pi / 4;
        if (solid(p + r * Vec2(std::cos(a), std::sin(a)))) return true;
      }
      return false;
    };
    open_.assign(g.size(), 0.0);
    centre_solid_.assign(g.size(), 0);
    const double wx = (g.hi.x() - g.lo.x()) / g.nx, wy = (g.hi.y() - g.lo.y()) / g.ny;
    for (int iy = 0; iy < g.ny; ++iy)
      for (int ix = 0; ix < g.nx; ++ix) {
        double free = 0;
        for (int a = 0; a < k; ++a)
          for (int c = 0; c < k; ++c) {
            const Vec2 p(g.lo.x() + (ix + (a + 0.5) / k) * wx, g.lo.y() + (iy + (c + 0.5) / k) * wy);
            if (excluded(p)) continue;
            double share = 1.0;
            for (const auto& ag : agents_) share *= ag->open_share(p, r);
            free += share;
          }
        open_[g.index(ix, iy)] = free / (k * k);
        centre_solid_[g.index(ix, iy)] = solid(g.centre(ix, iy));
      }
    open_grid_ = g;
    return open_;
  }

  std::unique_ptr<ed::Simulation> sim_ptr_;
  ed::Simulation& sim_;
  ed::CollapseGuard guard_;
  std::size_t reported_ = 0;             // overlap removals printed so far
  double first_mean_free_time_ = 0;      // of the first stats row with collisions (for messages)
  ed::FieldSampler* sampler_ = nullptr;     // owned by sim_
  std::vector<std::unique_ptr<EdAgentRun>> agents_;  // the table's agents the scene switched on
  std::optional<core::GridGeometry> open_grid_;      // the grid open_ was computed for
  std::vector<double> open_;
  std::vector<std::uint8_t> centre_solid_;  // the bin's centre is in a solid: masked
};

}  // namespace

EngineEntry ed_engine() {
  return {"ed", "2D event-driven hard disks (seed 003, Baryshev 2003)", &ed_keys::declare, &disk_attribute_names,
          [](const Scene& scene) -> std::unique_ptr<EngineRunner> { return std::make_unique<EdRunner>(scene); }};
}

}  // namespace grainflow::scenes
