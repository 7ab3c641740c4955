// `grainflow run` adapter of the 3D DEM engine (engine/dem): its keys (dem_keys.hpp) →
// dem::Config (SI units), frames of spheres coloured by the attributes of
// kSphereAttributes, stats rows of energies, contacts, wall forces and the pressure tensor,
// optionally pair.csv (the force–separation record of particles 1 and 2, seed 000 §5.4),
// and the table row.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "engine/io/atomic_file.hpp"
#include "engine/core/error.hpp"
#include "engine/io/particle_reader.hpp"
#include "engine/core/state_digest.hpp"
#include "engine/io/archive.hpp"
#include "engine/io/partial_file.hpp"
#include "engine/dem/field_sampler.hpp"
#include "engine/dem/simulation.hpp"
#include "engine/dem/pair_probe.hpp"
#include "scenes/src/engines/dem/dem_keys.hpp"
#include "scenes/src/engines/colour_attributes.hpp"
#include "scenes/src/engines/engine_runner.hpp"
#include "scenes/src/engines/engine_table.hpp"
#include "scenes/src/outputs/run_record.hpp"
#include "scenes/src/engines/field_snapshot.hpp"
#include "scenes/src/engines/initial_file.hpp"
#include "scenes/src/engines/sampling.hpp"
#include "scenes/src/scene/run_keys.hpp"
#include "scenes/src/scene/scene.hpp"

namespace grainflow::scenes {
namespace {

namespace keys = dem_keys;

// system.initial.kind = "file" (seed 000 §2.1, "read from a list"): one frame of
// system.initial.file (initial_file.hpp: the column mapping both engines share) gives
// positions, velocities, angular velocities, radii (0 or none → the group's radius) and
// masses (checked: DEM masses follow from radius and density); particle type t belongs to
// group t − 1, and each group's N must equal its type's count.
std::vector<dem::ParticleInit> particles_from_file(const Scene& sc, const dem::Config& c,
                                                   const std::vector<std::size_t>& counts) {
  const initial_file::InitialParticles f = initial_file::read(sc, 3, c.box.lo, c.box.hi);
  const std::string& what = f.what;
  std::size_t total = 0;
  for (auto n : counts) total += n;
  if (f.size() != total)
    throw Error(what + ": the file has " + std::to_string(f.size()) + " particles but the groups' N add up to " +
                std::to_string(total) + "; make the system.group N counts add up to the file's particle count");
  std::vector<std::size_t> seen(counts.size(), 0);
  std::vector<dem::ParticleInit> out(f.size());
  for (std::size_t i = 0; i < f.size(); ++i) {
    const int t = f.type[i];
    if (t < 1 || std::size_t(t) > counts.size())
      throw Error(what + ": particle " + std::to_string(i + 1) + " has type " + std::to_string(t) +
                  ", but the scene has " + std::to_string(counts.size()) +
                  " [[system.group]] table(s); allowed types: 1.." + std::to_string(counts.size()) +
                  " (type t is group t − 1)");
    dem::ParticleInit& p = out[i];
    p.x = f.position[i];
    p.group = t - 1;
    if (!f.radius.empty()) p.radius = f.radius[i];
    if (!f.velocity.empty()) p.v = f.velocity[i];
    if (!f.omega.empty()) p.omega = f.omega[i];
    if (!f.density.empty()) {
      const dem::GroupConfig& g = c.groups[std::size_t(p.group)];
      if (!(std::abs(f.density[i] - g.density) <= 1e-12 * g.density))
        throw Error(fmt::format("{}: particle {} has density {:.9g} kg/m³, but system.group[{}].density = {:.9g}; "
                                "make them equal, or list \"density\" in system.initial.ignore",
                                what, i + 1, f.density[i], p.group, g.density));
    }
    if (!f.mass.empty()) {
      const dem::GroupConfig& g = c.groups[std::size_t(p.group)];
      const double r = p.radius > 0 ? p.radius : g.radius;
      const double m = g.density * 4.0 / 3.0 * std::numbers::pi * r * r * r;
      if (!(std::abs(f.mass[i] - m) <= 1e-9 * m))
        throw Error(fmt::format("{}: particle {} has mass {:.9g} kg, but radius {:.9g} m at system.group[{}].density "
                                "= {:.9g} kg/m³ gives {:.9g} kg; set the density to match, or list \"mass\" in "
                                "system.initial.ignore",
                                what, i + 1, f.mass[i], r, p.group, g.density, m));
    }
    ++seen[std::size_t(t - 1)];
  }
  for (std::size_t g = 0; g < counts.size(); ++g)
    if (seen[g] != counts[g])
      throw Error("system.group[" + std::to_string(g) + "].N = " + std::to_string(counts[g]) + ", but " +
                  sc.get(initial_file::file) + " holds " + std::to_string(seen[g]) + " particles of type " +
                  std::to_string(g + 1) + "; N must equal the file's count of its type");
  return out;
}

dem::Config dem_config(const Scene& sc) {
  dem::Config c;
  const auto box = sc.get(keys::box);
  const auto lo = sc.get(keys::origin);
  c.box.lo = {lo[0], lo[1], lo[2]};
  c.box.hi = c.box.lo + Vec3(box[0], box[1], box[2]);
  const auto periodic = sc.get(keys::periodic);
  c.box.periodic = {periodic[0], periodic[1], periodic[2]};
  c.box.open_top = sc.get(keys::top) == "open";
  // Plane Couette: the z walls slide in their own plane (the schema allows only vx, vy).
  const auto top_v = sc.get(keys::top_velocity);
  const auto bottom_v = sc.get(keys::bottom_velocity);
  c.box.wall_velocity[5] = {top_v[0], top_v[1], 0.0};
  c.box.wall_velocity[4] = {bottom_v[0], bottom_v[1], 0.0};
  const auto g = sc.get(keys::gravity);
  c.gravity = {g[0], g[1], g[2]};
  if (auto dt = sc.find(keys::dt)) c.dt = *dt;
  c.steps_per_collision = int(sc.get(keys::steps_per_collision));
  c.neighbor = sc.get(keys::neighbor_search) == "all_pairs" ? dem::NeighborMethod::AllPairs
                                                                            : dem::NeighborMethod::ChainCells;
  if (const double skin = sc.get(keys::skin); skin > 0) c.skin = skin;

  c.model.normal = dem::normal_kind_from_name(sc.get(keys::normal_model));
  c.model.tangential = dem::tangential_kind_from_name(sc.get(keys::tangential_model));
  c.model.cohesion = sc.has(keys::vdw) ? dem::CohesionKind::VanDerWaals : dem::CohesionKind::None;

  c.groups.clear();
  std::vector<std::size_t> counts;
  for (std::size_t i = 0; i < sc.count(keys::group); ++i) {
    dem::GroupConfig gc;
    gc.radius = sc.get(keys::group_radius, i);
    gc.density = sc.get(keys::group_density, i);
    // A group's own value, else the system's (dem_keys.cpp: 0 or negative = not given).
    auto& p = gc.contact;
    const auto own = [&](const Key<double>& key, bool zero_is_given) {
      const double v = sc.get(key, i);
      return (v > 0.0 || (zero_is_given && v == 0.0)) ? std::optional<double>(v) : std::nullopt;
    };
    p.k1 = own(keys::group_kn, false).value_or(sc.get(keys::kn));
    p.kt = own(keys::group_kt, false).value_or(sc.get(keys::kt));
    p.e = own(keys::group_e, false).value_or(sc.get(keys::e));
    p.mu = own(keys::group_mu, true).value_or(sc.get(keys::mu));
    p.k2 = own(keys::group_k2, false).value_or(sc.find(keys::k2).value_or(0.0));
    p.gamma_n = own(keys::group_gamma_n, true).value_or(sc.find(keys::gamma_n).value_or(-1.0));
    p.gamma_t = own(keys::group_gamma_t, true).value_or(sc.find(keys::gamma_t).value_or(-1.0));
    p.damp_flag = sc.get(keys::dampflag);
    p.walton_gamma = sc.get(keys::walton_gamma);
    if (sc.has(keys::vdw)) {
      p.hamaker = sc.get(keys::vdw_A);
      p.alpha_min = sc.get(keys::vdw_alpha_min);
      p.alpha_cut = sc.get(keys::vdw_cutoff);
      p.vdw_radius = sc.get(keys::vdw_asperity_radius);
      p.r_ss = sc.get(keys::vdw_r_ss);
    }
    c.groups.push_back(gc);
    counts.push_back(std::size_t(sc.get(keys::group_N, i)));
  }

  // Initial positions (seed 000 §2.1): group 0's particles first, then group 1's.
  std::size_t total = 0;
  for (auto n : counts) total += n;
  double rmax = 0;
  for (const auto& gc : c.groups) rmax = std::max(rmax, gc.radius);
  const std::string kind = sc.get(keys::initial_kind);
  std::vector<Vec3> sites;
  if (kind == "lattice") {
    // Simple cubic, spread through the whole box (spacing cbrt(V/N), at least 2.04 r_max)
    // so a free-fall scene starts with the particles apart and falling, x fastest.
    const double volume = box[0] * box[1] * box[2];
    double a = std::max(2.04 * rmax, std::cbrt(volume / double(total)));
    auto sites_at = [&](double spacing) {
      return std::size_t(box[0] / spacing) * std::size_t(box[1] / spacing) * std::size_t(box[2] / spacing);
    };
    while (a > 2.04 * rmax && sites_at(a) < total) a = std::max(2.04 * rmax, a * 0.99);
    const int nx = int(box[0] / a), ny = int(box[1] / a), nz = int(box[2] / a);
    if (sites_at(a) < total)
      throw Error("system.initial.kind = \"lattice\": " + std::to_string(total) + " particles do not fit a " +
                  std::to_string(nx) + "×" + std::to_string(ny) + "×" + std::to_string(nz) +
                  " lattice at spacing 2.04 r in the box; enlarge system.box or lower the counts");
    sites = dem::simple_cubic_lattice(c.box.lo, a, nx, ny, nz);
    sites.resize(total);
  } else if (kind == "random") {
    // Placed at grow_from × the radius (in the lowest fill_height of the box when given),
    // then grown to the final radii over grow_steps (FINDRAD, §2.1).
    const auto grow = sc.get(keys::grow_steps);
    const double from = sc.get(keys::grow_from);
    c.growth_start = grow > 0 ? from : 1.0;
    c.growth_steps = std::uint64_t(grow);
    Vec3 hi = c.box.hi;
    if (const auto h = sc.find(keys::fill_height)) hi.z() = c.box.lo.z() + *h;
    sites = dem::random_positions(c.box.lo, hi, rmax * c.growth_start, total, std::uint64_t(sc.get(run_keys::seed)));
  } else {
    c.particles = particles_from_file(sc, c, counts);
    return c;
  }
  std::size_t k = 0;
  for (std::size_t gi = 0; gi < counts.size(); ++gi)
    for (std::size_t j = 0; j < counts[gi]; ++j, ++k) {
      dem::ParticleInit p;
      p.x = sites[k];
      p.group = int(gi);
      c.particles.push_back(p);
    }
  return c;
}

// Fields are averaged over each exposure from sample_keys::kSamplesPerExposure snapshots of
// the state, on the plane sample.plane (averaged across the box normal to it).

core::BinningOptions binning_options(const Scene& sc, const dem::Config& cfg) {
  const core::BinPlane plane = core::bin_plane(sc.get(keys::plane));
  const auto [u, v] = core::plane_axes(plane);
  // Bins of at least two of the largest diameters unless sample.bins says otherwise: a
  // sphere is binned by its centre, so finer bins stripe the density with the layers.
  double rmax = 0;
  for (const auto& g : cfg.groups) rmax = std::max(rmax, g.radius);
  for (const auto& p : cfg.particles) rmax = std::max(rmax, p.radius);
  const Vec2 extent(cfg.box.hi[u] - cfg.box.lo[u], cfg.box.hi[v] - cfg.box.lo[v]);
  const std::array<int, 2> bins = sc.find(sample_keys::bins).value_or(core::bins_no_finer_than(extent, 4.0 * rmax));
  std::optional<std::array<double, 2>> slab;
  if (const auto s = sc.find(keys::slab)) slab = *s;
  return core::plane_binning(plane, cfg.box.lo, cfg.box.hi, bins, slab);
}

// pair.csv (output.pair_csv): particles 1 and 2 of the scene every output.pair_every
// steps, the force–separation record of Fig. 5.6–5.16 as dem::sample_pair measures it
// (engine/dem/pair_probe.hpp: separation α, normal_force, vdw_force = the cohesion
// sub-model's attraction, contact_force, v_rel_n). Written as pair.csv.partial until the run ends (io::PartialFile).
class PairProbe final : public RunOutput {
public:
  PairProbe(std::filesystem::path file, const dem::Simulation& sim) : path_(std::move(file)), sim_(sim) {}

  void start(const RunRecord&) override {
    file_.emplace(io::PartialFile::create(path_));
    file_->write("step,time,separation,normal_force,vdw_force,contact_force,v_rel_n\n");
    record();
  }
  void checkpoint(io::ArchiveWriter& w) override {
    file_->flush();
    w.tag("pair.csv");
    w.pod(file_->size());
  }
  void resume(io::ArchiveReader& r, const RunRecord&) override {
    r.tag("pair.csv");
    file_.emplace(io::PartialFile::resume(path_, r.get<std::uint64_t>()));
  }
  void record() {
    const dem::PairSample p = dem::sample_pair(sim_, 0, 1);
    file_->write(fmt::format("{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", sim_.steps(), sim_.time(),
                             p.separation, p.normal_force, p.cohesion_force, p.contact_force, p.v_rel_n));
  }
  void finish(const RunRecord&) override { file_->finish(); }

private:
  std::filesystem::path path_;
  const dem::Simulation& sim_;
  std::optional<io::PartialFile> file_;
};

// What render.color_by may colour a sphere by: the one list the schema offers and the
// snapshot computes.
struct SphereAttribute {
  std::string_view name;
  double (*value)(const dem::Simulation& sim, std::size_t i);
  bool categorical = false;
};
constexpr SphereAttribute kSphereAttributes[] = {
    {"uniform", nullptr},
    {"speed", [](const dem::Simulation& sim, std::size_t i) { return sim.velocity(i).norm(); }},
    {"vx", [](const dem::Simulation& sim, std::size_t i) { return sim.velocity(i).x(); }},
    {"vy", [](const dem::Simulation& sim, std::size_t i) { return sim.velocity(i).y(); }},
    {"vz", [](const dem::Simulation& sim, std::size_t i) { return sim.velocity(i).z(); }},
    {"spin", [](const dem::Simulation& sim, std::size_t i) { return sim.angular_velocity(i).norm(); }},
    {"group", [](const dem::Simulation& sim, std::size_t i) { return double(sim.group(i)); }, true},
    {"height", [](const dem::Simulation& sim, std::size_t i) { return sim.position(i).z(); }},
};

std::vector<std::string> sphere_attribute_names() { return attribute_names<SphereAttribute>(kSphereAttributes); }
const SphereAttribute& sphere_attribute(std::string_view name) { return find_attribute<SphereAttribute>(kSphereAttributes, name); }

class DemRunner final : public EngineRunner {
public:
  explicit DemRunner(const Scene& sc)
      : sim_(dem_config(sc)),
        fields_(binning_options(sc, sim_.config())),
        sample_every_(sample_keys::sample_interval(sc.get(sample_keys::exposure))),
        next_sample_(sim_.time() + sample_every_),
        fields_begin_(sim_.time()),
        scene_(sc),
        pair_every_(std::uint64_t(sc.get(keys::pair_every))) {}

  std::vector<std::unique_ptr<RunOutput>> open_outputs(const OutputContext& context) override {
    std::vector<std::unique_ptr<RunOutput>> out;
    if (!scene_.get(keys::pair_csv)) return out;
    if (sim_.size() < 2)
      throw Error("output.pair_csv = true needs at least 2 particles; the scene has " + std::to_string(sim_.size()));
    context.claim("pair.csv");
    auto probe = std::make_unique<PairProbe>(context.dir / "pair.csv", sim_);
    pair_ = probe.get();
    out.push_back(std::move(probe));
    return out;
  }

  double time() const override { return sim_.time(); }
  void advance_to(double t) override {
    // Whole steps only: stop at the last step not past t (at least one step), sampling
    // the fields on the way; after ~10^7 particle-steps (≈ 0.3 s) control goes back to
    // the run loop.
    const std::uint64_t budget = std::max<std::uint64_t>(1, 10'000'000 / std::max<std::size_t>(1, sim_.size()));
    const std::uint64_t start = sim_.steps();
    while (sim_.steps() - start < budget) {
      const double until = std::min(t, next_sample_);
      const double steps = std::floor((until - sim_.time()) / sim_.dt() + 1e-9);
      step(std::min(std::uint64_t(std::max(1.0, steps)), budget - (sim_.steps() - start)));
      if (sim_.time() >= next_sample_ - 0.5 * sim_.dt()) {
        dem::sample_fields(sim_, fields_);
        next_sample_ += sample_every_;
      }
      if (sim_.time() >= t - 0.5 * sim_.dt()) break;
    }
    sample_pressure();
  }
  void advance_steps(std::uint64_t n) override {
    step(n);
    sample_pressure();
  }
  std::uint64_t steps_done() const override { return sim_.steps(); }

  void snapshot(const std::string& colour_by, render::Snapshot& s) override {
    const auto& b = sim_.config().box;
    s.dim = 3;
    s.lo = b.lo;
    s.hi = b.hi;
    s.periodic = b.periodic;
    s.open_faces = {false, false, false, false, false, b.open_top};
    s.time = sim_.time();
    s.time_unit = "s";
    s.length_unit = "m";
    const std::size_t n = sim_.size();
    s.pos_radius.resize(4 * n);
    s.attribute.clear();
    s.attribute_name = colour_by;
    const SphereAttribute& attribute = sphere_attribute(colour_by);
    s.attribute_categorical = attribute.categorical;
    if (attribute.value) s.attribute.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 x = sim_.position(i);
      float* p = &s.pos_radius[4 * i];
      p[0] = float(x.x());
      p[1] = float(x.y());
      p[2] = float(x.z());
      p[3] = float(sim_.radius(i));
      if (attribute.value) s.attribute[i] = float(attribute.value(sim_, i));
    }
    s.obstacles.clear();
    // The fields of a frame are averaged since the frame before: the first has none yet.
    s.fields_pending = fields_.frames() > 0 ? std::string() : "fields from the next frame (averaged since this one)";
    if (fields_.frames() > 0) {
      core::BinnedFields f;
      f.density = fields_.density();
      f.fraction = fields_.fraction();
      f.mean_velocity = fields_.mean_velocity();
      f.temperature = fields_.temperature();
      f.mean_speed = fields_.mean_speed();
      f.counts = fields_.counts();
      const std::array<int, 2> axes = core::plane_axes(fields_.options().plane);
      // SI: m<C²>/3 with the masses in kg (core::BinAccumulator::temperature), in J: the
      // granular_temperature of the field files, labelled as what it is.
      const core::BinningOptions& o = fields_.options();
      std::optional<std::array<double, 2>> slab;
      if (o.slab_lo && o.slab_hi) slab = std::array{*o.slab_lo, *o.slab_hi};
      set_binned_fields(std::move(f), s, {"m⁻²", "J", "m/s", "1/s", "m<C²>/3"},
                        render::FieldExposure{fields_begin_, sim_.time(), fields_.frames(), axes, slab});
      fields_.reset();
      fields_begin_ = sim_.time();
    }
  }

  void particles(core::ParticleFrame& f) const override {
    const auto& b = sim_.config().box;
    f.clear();
    f.dim = 3;
    f.time = sim_.time();
    f.timestep = std::int64_t(sim_.steps());
    f.has_box = true;
    f.box_lo = b.lo;
    f.box_hi = b.hi;
    f.periodic = b.periodic;
    const std::size_t n = sim_.size();
    std::vector<double> wx(n), wy(n), wz(n), mass(n);
    for (std::size_t i = 0; i < n; ++i) {
      // Persistent: the DEM engine never adds, removes or reorders particles, so the
      // index a particle was built with stays its own for the whole run (and its resumes).
      f.id.push_back(std::int64_t(i + 1));
      f.type.push_back(sim_.group(i) + 1);
      f.position.push_back(sim_.position(i));
      f.radius.push_back(sim_.radius(i));
      f.velocity.push_back(sim_.velocity(i));
      const Vec3 w = sim_.angular_velocity(i);
      wx[i] = w.x();
      wy[i] = w.y();
      wz[i] = w.z();
      mass[i] = sim_.mass(i);
    }
    f.extra = {{"omegax", std::move(wx)}, {"omegay", std::move(wy)}, {"omegaz", std::move(wz)}, {"mass", std::move(mass)}};
  }

  // Every column is the state at the row's time (no window), but the pressure tensor: the
  // mean of its samples since the previous row (an instantaneous virial is noisy).
  std::vector<StatsColumn> stats_columns() const override {
    return {{"step", "1", "time steps taken since the start"},
            {"N", "1", "particles in the system (the DEM engine neither inserts nor removes any)"},
            {"kinetic_energy", "J", "Σ m|v|²/2, velocities at the full step (v_n = v_{n−1/2} + Δt F_n/(2m), seed 000 Eq. 2.19)"},
            {"rotational_energy", "J", "Σ I|ω|²/2"},
            {"potential_energy", "J", "gravitational potential energy Σ −m g·x (zero at the origin)"},
            {"contacts", "1", "particle–particle pairs with overlap > 0"},
            {"coordination", "1", "mean contacts per particle, 2 contacts / N"},
            {"wall_force_bottom_z", "N", "z component of the force the particles exert on the z-lo wall"},
            {"neighbour_builds", "1", "Verlet neighbour list rebuilds since the start"},
            {"pressure", "Pa",
             "(P_xx + P_yy + P_zz)/3: the mean pressure over the stats window, of the same samples as P_xx"},
            {"P_xx", "Pa",
             "pressure tensor xx, the mean of its samples since the previous row, taken at the end of every slice "
             "the run advances by (at most exposure/20 apart; the row's own time included). A sample is the state "
             "at its step: [Σ m (v_x − V_x)² + W_xx] / vol; v the full-step velocities, V the mass-averaged "
             "velocity, vol = lx·ly·lz the box volume; W the contact virial Σ_pairs r_ij,x F_ij,x (r_ij = x_i − "
             "x_j across the periodic image the force acts through, F_ij the force on i) + Σ_wall contacts r_x F_x (r = "
             "the centre minus its foot on the wall: the Love–Weber stress of all particles, wall-bound ones included); "
             "gravity adds nothing (it acts at the centres, as LAMMPS's fix gravity adds no virial)"},
            {"P_yy", "Pa", "pressure tensor yy: [Σ m (v_y − V_y)² + W_yy] / vol, averaged as P_xx"},
            {"P_zz", "Pa", "pressure tensor zz: [Σ m (v_z − V_z)² + W_zz] / vol, averaged as P_xx"},
            {"P_xy", "Pa",
             "pressure tensor xy: [Σ m (v_x − V_x)(v_y − V_y) + Σ (r_x F_y + r_y F_x)/2] / vol, averaged as P_xx "
             "(symmetrised; the contacts of P_xx; LAMMPS's compute pressure reports Σ r_x F_y, which differs by half the "
             "net contact torque, zero for frictionless contacts and at rest)"},
            {"P_xz", "Pa",
             "pressure tensor xz: [Σ m (v_x − V_x)(v_z − V_z) + Σ (r_x F_z + r_z F_x)/2] / vol, averaged as P_xx "
             "(symmetrised; for a Couette flow along x between walls normal to z, −P_xz is the shear stress)"},
            {"P_yz", "Pa",
             "pressure tensor yz: [Σ m (v_y − V_y)(v_z − V_z) + Σ (r_y F_z + r_z F_y)/2] / vol, averaged as P_xx "
             "(symmetrised)"}};
  }
  void check_finite() const override { require_finite(sim_.stats()); }

  std::vector<double> stats_row() override {
    const dem::Stats st = sim_.stats();
    require_finite(st);
    if (pressure_samples_ == 0) sample_pressure();  // a row before any advance: the state now
    std::array<double, 6> p;
    for (int k = 0; k < 6; ++k) p[k] = pressure_sum_[k] / double(pressure_samples_);
    pressure_sum_.fill(0.0);
    pressure_samples_ = 0;
    return {double(st.step),        double(sim_.size()), st.kinetic,           st.rotational,
            st.potential_gravity,   double(st.contacts), st.coordination,      st.wall_force[4].z(),
            double(st.neighbor_builds), (p[0] + p[1] + p[2]) / 3.0, p[0], p[1], p[2], p[3], p[4], p[5]};
  }

  double work() const override { return double(sim_.steps()) * double(sim_.size()); }
  std::string work_unit() const override { return "particle-steps"; }
  std::vector<std::pair<std::string, double>> figures() const override {
    return {{"steps", double(sim_.steps())},
            {"particles", double(sim_.size())},
            {"dt", sim_.dt()},
            {"threads", double(dem::thread_count())}};
  }
  void save(io::ArchiveWriter& w) const override {
    sim_.save_state(w);
    w.tag("dem.runner");
    io::save(w, fields_);  // the exposure being accumulated
    w.pod(next_sample_);
    w.pod(fields_begin_);
    w.pod(pressure_sum_);  // the stats window being accumulated
    w.pod(pressure_samples_);
  }
  void load(io::ArchiveReader& r) override {
    sim_.load_state(r);
    r.tag("dem.runner");
    io::load(r, fields_);
    r.pod(next_sample_);
    r.pod(fields_begin_);
    r.pod(pressure_sum_);
    r.pod(pressure_samples_);
  }

  std::string state_digest() const override {
    // Positions, velocities and spins in particle order, through the public accessors so
    // the digest does not depend on the engine's internal layout.
    core::StateDigest d;
    d.add(sim_.time());
    for (std::size_t i = 0; i < sim_.size(); ++i)
      for (const Vec3& q : {sim_.position(i), sim_.velocity(i), sim_.angular_velocity(i)})
        d.add(std::span<const double>(q.data(), 3));
    return d.hex();
  }

private:
  // A state that has turned non-finite: see EngineRunner::check_finite.
  void require_finite(const dem::Stats& st) const {
    // A state that has turned non-finite (forces beyond what the time step can hold, an
    // absurd gravity) would run on to "complete" with NaN everywhere: stop it as failed.
    for (const auto& [name, v] : {std::pair{"kinetic energy", st.kinetic}, std::pair{"rotational energy", st.rotational},
                                  std::pair{"potential energy", st.potential_gravity}})
      if (!std::isfinite(v))
        throw Error(fmt::format("dem: the state is no longer finite at t = {:.6g} s: {} = {} (check system.gravity, "
                                "the stiffnesses and the time step)",
                                sim_.time(), name, v));
  }


  // One sample of the pressure tensor's stats window, at the end of an advance: always
  // after a whole slice of the run, so a resumed run takes the same samples.
  void sample_pressure() {
    const std::array<double, 6> p = sim_.pressure_tensor();
    for (int k = 0; k < 6; ++k) pressure_sum_[k] += p[k];
    ++pressure_samples_;
  }

  // Steps the engine, stopping every pair_every steps for the pair record when asked.
  void step(std::uint64_t n) {
    if (!pair_) return sim_.step(n);
    while (n > 0) {
      const std::uint64_t k = std::min(n, pair_every_ - sim_.steps() % pair_every_);
      sim_.step(k);
      n -= k;
      if (sim_.steps() % pair_every_ == 0) pair_->record();
    }
  }

  dem::Simulation sim_;
  core::BinAccumulator fields_;
  double sample_every_, next_sample_;
  double fields_begin_;  // when the exposure being accumulated began
  Scene scene_;
  std::uint64_t pair_every_;
  PairProbe* pair_ = nullptr;  // owned by the run loop with the other outputs, when asked for
  std::array<double, 6> pressure_sum_{};  // Σ of the samples since the last stats row
  std::uint64_t pressure_samples_ = 0;
};

}  // namespace

EngineEntry dem_engine() {
  return {"dem", "3D soft-sphere DEM with Walton contacts (seed 000, Sweetman 2003)", &dem_keys::declare,
          &sphere_attribute_names,
          [](const Scene& scene) -> std::unique_ptr<EngineRunner> { return std::make_unique<DemRunner>(scene); }};
}

}  // namespace grainflow::scenes
