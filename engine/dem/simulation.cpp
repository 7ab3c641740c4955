#include "engine/dem/simulation.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "engine/core/error.hpp"
#include "engine/core/rng.hpp"
#include "engine/dem/simd_clones.hpp"
#include "engine/dem/time_step.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace grainflow::dem {

namespace {

std::string num(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

std::string vec(const Vec3& v) { return "(" + num(v.x()) + ", " + num(v.y()) + ", " + num(v.z()) + ")"; }

double group_mass(const GroupConfig& g) {
  return 4.0 / 3.0 * std::numbers::pi * g.radius * g.radius * g.radius * g.density;
}

// The per-particle end of a force evaluation for particles [i0, i1): gravity added to F,
// then the leap-frog kick and drift (Eq. 2.19) of the next step; returns the largest
// squared displacement since the last neighbour build (0 without kick). SIMD over the
// x, y, z components as one flat array: the per-particle factors are first spread to
// the three components of a block, so that no loop needs stride-3 shuffles.
template <bool kGravity, bool kKick>
GRAINFLOW_DEM_SIMD_CLONES double gravity_kick_drift(Particles& P, const NeighborList& L, std::size_t i0,
                                                    std::size_t i1, const Vec3& g, double kick, double dt) {
  constexpr std::size_t kBlock = 256;  // particles; the spread factors stay in L1
  double* __restrict f = P.f.data();
  const double* __restrict t = P.t.data();
  double* __restrict v = P.v.data();
  double* __restrict x = P.x.data();
  double* __restrict w = P.w.data();
  const double* __restrict mass = P.mass.data();
  const double* __restrict inv_mass = P.inv_mass.data();
  const double* __restrict inv_inertia = P.inv_inertia.data();
  const double* __restrict xref = L.xref.data();
  const double gc[3] = {g.x(), g.y(), g.z()};
  double mg[3 * kBlock], ki[3 * kBlock], kr[3 * kBlock], d2[3 * kBlock];
  double dmax = 0.0;
  for (std::size_t b0 = i0; b0 < i1; b0 += kBlock) {
    const std::size_t nb = std::min(kBlock, i1 - b0), k0 = 3 * b0, nk = 3 * nb;
    for (std::size_t l = 0; l < nb; ++l)
      for (int c = 0; c < 3; ++c) {
        mg[3 * l + c] = mass[b0 + l] * gc[c];
        ki[3 * l + c] = kick * inv_mass[b0 + l];
        kr[3 * l + c] = kick * inv_inertia[b0 + l];
      }
#pragma omp simd
    for (std::size_t k = 0; k < nk; ++k) {
      double fk = f[k0 + k];
      if constexpr (kGravity) {
        fk = fk + mg[k];
        f[k0 + k] = fk;
      }
      if constexpr (kKick) {
        const double vk = v[k0 + k] + ki[k] * fk;
        const double xk = x[k0 + k] + dt * vk;
        v[k0 + k] = vk;
        x[k0 + k] = xk;
        w[k0 + k] = w[k0 + k] + kr[k] * t[k0 + k];
        const double d = xk - xref[k0 + k];
        d2[k] = d * d;
      }
    }
    if constexpr (kKick)
      for (std::size_t l = 0; l < nb; ++l) dmax = std::max(dmax, d2[3 * l] + d2[3 * l + 1] + d2[3 * l + 2]);
  }
  return dmax;
}

// Start of the k-th of `parts` contiguous runs of chunks of about equal total cost (the
// prefix sum nearest k/parts of the total); `cost` empty: equal numbers of chunks.
std::size_t balanced_split(const std::vector<double>& cost, std::size_t nchunks, std::size_t parts, std::size_t k) {
  if (k == 0 || k >= parts) return k == 0 ? 0 : nchunks;
  if (cost.empty()) return nchunks * k / parts;
  double total = 0.0;
  for (double c : cost) total += c;
  const double target = total * static_cast<double>(k) / static_cast<double>(parts);
  std::size_t best = 0;
  double prefix = 0.0, best_gap = target;
  for (std::size_t c = 1; c <= nchunks; ++c) {
    prefix += cost[c - 1];
    if (std::abs(prefix - target) < best_gap) {
      best_gap = std::abs(prefix - target);
      best = c;
    }
  }
  return best;
}

// This thread's place in the enclosing parallel region and the region's size.
struct TeamSlot {
  std::size_t index = 0, size = 1;
};
TeamSlot team_slot() {
#ifdef _OPENMP
  return {static_cast<std::size_t>(omp_get_thread_num()), static_cast<std::size_t>(omp_get_num_threads())};
#else
  return {};
#endif
}

}  // namespace

int thread_count() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

void set_thread_count([[maybe_unused]] int n) {
#ifdef _OPENMP
  if (n > 0) omp_set_num_threads(n);
#endif
}

Simulation::Simulation(Config cfg) : cfg_(std::move(cfg)) { setup(); }
Simulation::~Simulation() = default;
Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;

double Simulation::centre_distance_sq(std::size_t i, std::uint32_t q) const {
  const std::uint32_t j = list_.partner[q];
  const double* sh = box_.shift[list_.shift[q]];
  double d2 = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double d = p_.x[3 * j + a] + sh[a] - p_.x[3 * i + a];
    d2 += d * d;
  }
  return d2;
}

void Simulation::setup() {
  configure();
  place_particles();
}

void Simulation::configure() {
  const Config& c = cfg_;
  // ---- groups and contact parameters
  if (c.groups.empty() || c.groups.size() > 2)
    throw Error("dem: groups has " + std::to_string(c.groups.size()) + " entries; 1 or 2 are allowed");
  for (std::size_t g = 0; g < c.groups.size(); ++g) {
    const std::string where = "groups[" + std::to_string(g) + "]";
    if (!(c.groups[g].radius > 0.0))
      throw Error("dem: " + where + ".radius = " + num(c.groups[g].radius) + " m; it must be > 0");
    if (!(c.groups[g].density > 0.0))
      throw Error("dem: " + where + ".density = " + num(c.groups[g].density) + " kg/m3; it must be > 0");
    validate(c.groups[g].contact, c.model, where + ".contact");
  }
  if (c.mixed_contact) validate(*c.mixed_contact, c.model, "mixed_contact");
  const int ng = static_cast<int>(c.groups.size());
  std::array<ContactParams, 9> per{};
  std::array<double, 9> meff{};
  double mg[2];
  for (int g = 0; g < 2; ++g) mg[g] = group_mass(c.groups[std::min(g, ng - 1)]);
  for (int a = 0; a < 2; ++a) {
    const GroupConfig& ga = c.groups[std::min(a, ng - 1)];
    for (int b = 0; b < 2; ++b) {
      const GroupConfig& gb = c.groups[std::min(b, ng - 1)];
      per[type_pair(a, b)] = a == b || ng == 1 ? ga.contact : (c.mixed_contact ? *c.mixed_contact : mix(ga.contact, gb.contact));
      meff[type_pair(a, b)] = mg[a] * mg[b] / (mg[a] + mg[b]);
    }
    // Walls: the group's own parameters; a damping rate derived from e refers to a pair
    // of two equal particles, as LAMMPS's single γn does.
    per[type_pair(a, kWallType)] = ga.contact;
    meff[type_pair(a, kWallType)] = 0.5 * mg[a];
  }
  law_ = make_contact_law(c.model, per, meff);

  // ---- time step (Eq. 2.23) and stability limit, as the chosen sub-models give them
  double tc_min = 1e300, lim = 1e300;
  for (int a = 0; a < ng; ++a)
    for (int b = 0; b <= ng; ++b) {
      const int tp = type_pair(a, b == ng ? kWallType : b);
      const double mu = b == ng ? mg[a] : mg[a] * mg[b] / (mg[a] + mg[b]);
      const double tc = collision_time(c.model, per[tp], mu, meff[tp]);
      if (tc > 0.0) tc_min = std::min(tc_min, tc);
      lim = std::min(lim, stability_limit(c.model, per[tp], mu));
    }
  dt_limit_ = lim;
  if (c.dt > 0.0) {
    if (c.dt > dt_limit_)
      throw Error("dem: dt = " + num(c.dt) + " s is above the stability limit " + num(dt_limit_) +
                  " s of the stiffest contact spring (2·sqrt(m_red/k)); use dt ≤ " + num(dt_limit_) +
                  " s or dt = 0 to derive it from steps_per_collision (Eq. 2.23)");
    dt_ = c.dt;
  } else if (c.dt == 0.0) {
    if (c.steps_per_collision < 1)
      throw Error("dem: steps_per_collision = " + std::to_string(c.steps_per_collision) + "; it must be ≥ 1 (40–60 advised)");
    dt_ = tc_min / c.steps_per_collision;
    if (dt_ > dt_limit_)
      throw Error("dem: steps_per_collision = " + std::to_string(c.steps_per_collision) + " gives dt = " + num(dt_) +
                  " s above the stability limit " + num(dt_limit_) + " s; use more steps per collision");
  } else {
    throw Error("dem: dt = " + num(c.dt) + " s; it must be > 0, or 0 to use Eq. 2.23");
  }

  // ---- box
  for (int a = 0; a < 3; ++a) {
    box_.lo[a] = c.box.lo[a];
    box_.hi[a] = c.box.hi[a];
    box_.periodic[a] = c.box.periodic[a];
    if (!(c.box.hi[a] > c.box.lo[a]))
      throw Error("dem: box.hi " + vec(c.box.hi) + " must exceed box.lo " + vec(c.box.lo) + " on every axis");
  }
  box_.finalize();
  for (int w = 0; w < 6; ++w) {
    box_.wall[w] = !box_.periodic[w / 2] && !(w == 5 && c.box.open_top);
    const Vec3& u = c.box.wall_velocity[w];
    if (u[w / 2] != 0.0)
      throw Error("dem: box.wall_velocity[" + std::to_string(w) + "] = " + vec(u) +
                  " has a component normal to the wall; only in-plane velocities are allowed");
    for (int a = 0; a < 3; ++a) box_.wall_vel[w][a] = u[a];
  }

}

void Simulation::place_particles() {
  const Config& c = cfg_;
  const int ng = static_cast<int>(c.groups.size());
  // ---- particles
  const std::size_t n = c.particles.size();
  p_.resize(n);
  final_radius_.assign(n, 0.0);
  if (c.growth_steps > 0 && !(c.growth_start > 0.0 && c.growth_start <= 1.0))
    throw Error("dem: growth_start = " + num(c.growth_start) + "; the starting radius fraction must be in (0, 1]");
  const double g0 = c.growth_steps > 0 ? c.growth_start : 1.0;
  double rmax = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const ParticleInit& pi = c.particles[i];
    if (pi.group < 0 || pi.group >= ng)
      throw Error("dem: particles[" + std::to_string(i) + "].group = " + std::to_string(pi.group) + "; allowed 0.." +
                  std::to_string(ng - 1));
    const GroupConfig& g = c.groups[pi.group];
    const double rf = pi.radius > 0.0 ? pi.radius : g.radius;
    if (!(rf > 0.0) || !std::isfinite(rf))
      throw Error("dem: particles[" + std::to_string(i) + "].radius = " + num(rf) + " m; it must be > 0");
    const double r = g0 * rf;
    for (int a = 0; a < 3; ++a) {
      const double x = pi.x[a];
      const bool inside = std::isfinite(x) && x >= box_.lo[a] && (x < box_.hi[a] || (a == 2 && c.box.open_top));
      if (!inside)
        throw Error("dem: particles[" + std::to_string(i) + "] at " + vec(pi.x) + " m is outside the box " + vec(c.box.lo) +
                    " – " + vec(c.box.hi));
      if (box_.wall[2 * a] && x - box_.lo[a] < r)
        throw Error("dem: particles[" + std::to_string(i) + "] at " + vec(pi.x) + " (radius " + num(r) +
                    " m) overlaps the wall at " + "xyz"[a] + " = " + num(box_.lo[a]));
      if (box_.wall[2 * a + 1] && box_.hi[a] - x < r)
        throw Error("dem: particles[" + std::to_string(i) + "] at " + vec(pi.x) + " (radius " + num(r) +
                    " m) overlaps the wall at " + "xyz"[a] + " = " + num(box_.hi[a]));
      p_.x[3 * i + a] = x;
      p_.v[3 * i + a] = pi.v[a];
      p_.w[3 * i + a] = pi.omega[a];
    }
    p_.radius[i] = r;
    final_radius_[i] = rf;
    p_.mass[i] = 4.0 / 3.0 * std::numbers::pi * rf * rf * rf * g.density;
    p_.inv_mass[i] = 1.0 / p_.mass[i];
    p_.inv_inertia[i] = 1.0 / (0.4 * p_.mass[i] * rf * rf);
    p_.group[i] = static_cast<std::uint8_t>(pi.group);
    rmax = std::max(rmax, rf);
  }
  skin_ = c.skin < 0.0 ? 0.4 * rmax : c.skin;
  if (!std::isfinite(skin_)) throw Error("dem: skin = " + num(c.skin) + " m; it must be finite and ≥ 0");

  list_.history_size = law_->history_size();
  wall_hist_.assign(6 * n * law_->history_size(), 0.0);
  wall_flags_.assign(6 * n, 0);
  rebuild();
  // Overlapping initial positions are a configuration error, not something to blow apart.
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint32_t q = list_.first[i]; q < list_.first[i + 1]; ++q) {
      const std::uint32_t j = list_.partner[q];
      const double d2 = centre_distance_sq(i, q);
      const double rs = p_.radius[i] + p_.radius[j];
      if (d2 < rs * rs)
        throw Error("dem: particles[" + std::to_string(i) + "] and particles[" + std::to_string(j) +
                    "] overlap (centre distance " + num(std::sqrt(d2)) + " m < sum of radii " + num(rs) +
                    " m); initial positions must not overlap");
    }
  // Forces at t = 0 for the first (half) kick; like LAMMPS's setup, history is not updated.
  compute_forces(false, false);
}

void Simulation::rebuild() {
  build_neighbor_list(list_, p_, box_, skin_, law_->cohesion_range(), cfg_.neighbor);
  need_rebuild_ = false;
  update_wall_near();
}

void Simulation::update_wall_near() {
  // Walls each particle may reach before the next rebuild (it moves < skin/2 from its
  // position at the build); walls with live history stay marked so it gets cleared.
  wall_first_.assign(p_.n + 1, 0);
  wall_slot_.clear();
  const double reach = law_->cohesion_range() + skin_;
  for (std::size_t i = 0; i < p_.n; ++i) {
    for (int w = 0; w < 6; ++w) {
      if (!box_.wall[w]) continue;
      const int a = w / 2;
      const double x = list_.xref[3 * i + a];
      const double dist = w % 2 == 0 ? x - box_.lo[a] : box_.hi[a] - x;
      if (dist < p_.radius[i] + reach || wall_flags_[6 * i + w] != 0) wall_slot_.push_back(static_cast<std::uint32_t>(6 * i + w));
    }
    wall_first_[i + 1] = static_cast<std::uint32_t>(wall_slot_.size());
  }
}

std::size_t Simulation::force_chunks() const {
  const std::size_t kChunk = force_chunk_size(p_.n);
  return (p_.n + kChunk - 1) / kChunk;
}

void Simulation::begin_force_pass(bool update, bool then_integrate) {
  const std::size_t nchunks = force_chunks();
  chunk_wall_.assign(nchunks * 18, 0.0);
  chunk_disp_.assign(nchunks, 0.0);
  // The virial only where the pass's forces remain the state's (the end of a step()
  // batch, the set-up): a stats row reads it, the passes in between need not pay for it.
  pass_.virial = !then_integrate;
  if (pass_.virial) chunk_virial_.assign(nchunks * 12, 0.0);
  if (!sync_) sync_ = std::make_unique<ThreadSync>();
  sync_->resize(nchunks);
  if (chunk_time_.size() != 2 * nchunks) {
    chunk_cost_.clear();  // until measured: equal shares
    chunk_time_.assign(2 * nchunks, 0.0);
  }
  pass_.update = update;
  pass_.integrate = then_integrate;
  pass_.kick = started_ ? dt_ : 0.5 * dt_;
  pass_.number = ++force_passes_;  // wraps: only equality with the current pass counts
  pass_.team = 1;
}

void Simulation::force_pass_share(std::size_t t, std::size_t T) {
  const std::size_t n = p_.n;
  const std::size_t kChunk = force_chunk_size(n);  // fixed work unit: independent of thread count
  const std::size_t nchunks = force_chunks();
  const double kick = pass_.kick, dt = dt_;
  const bool then_integrate = pass_.integrate, with_virial = pass_.virial;
  const std::uint32_t pass = pass_.number;
  ForcePass fp;
  fp.p = &p_;
  fp.list = &list_;
  fp.box = &box_;
  fp.wall_hist = wall_hist_.data();
  fp.wall_flags = wall_flags_.data();
  fp.wall_first = wall_first_.data();
  fp.wall_slot = wall_slot_.data();
  fp.dt = dt_;
  fp.update = pass_.update;
  const Vec3& g = cfg_.gravity;
  Particles& P = p_;
  const NeighborList& L = list_;
  const ContactLaw& law = *law_;
  ThreadSync& sync = *sync_;
  if (t == 0) pass_.team = T;

  // Pair pass of chunk c: its own pairs, shares to its own particles at once and to later
  // chunks' particles through cross-force slots.
  auto pair_part = [&](std::size_t c) {
    law.pair_pass(fp, c * kChunk, std::min(n, (c + 1) * kChunk), with_virial ? &chunk_virial_[12 * c] : nullptr);
    if (T > 1) sync.publish(sync.chunk(c).pass, pass);
  };
  // The rest of chunk c, once it and the chunks with pairs into it have had their pair pass
  // (see NeighborList::chunk_dep): cross shares, walls, gravity, and the next kick and drift
  // while its particles are still in cache.
  auto wait_deps = [&](std::size_t c) {
    for (std::size_t d = L.chunk_dep[c]; d <= c; ++d) sync.wait_for(sync.chunk(d).pass, pass);
  };
  auto rest_part = [&](std::size_t c) {
    const std::size_t i0 = c * kChunk, i1 = std::min(n, (c + 1) * kChunk);
    // Each particle sums its pairs in a fixed order (the pair pass: shares from owners in
    // its chunk, own pairs by ascending j; then owners in earlier chunks by ascending i):
    // independent of the thread count.
    for (std::size_t i = i0; i < i1; ++i) {
      double f0 = 0, f1 = 0, f2 = 0, t0 = 0, t1 = 0, t2 = 0;
      for (std::size_t k = L.rfirst[i]; k < L.rfirst[i + 1]; ++k) {
        const double* pf = &L.cross_force[k * 6];  // zero while the pair is inactive
        f0 -= pf[0]; f1 -= pf[1]; f2 -= pf[2];
        t0 += pf[3]; t1 += pf[4]; t2 += pf[5];
      }
      // Torque R_i Σ (n × F_t) over all the particle's contacts.
      const double ri = P.radius[i];
      double* f = &P.f[3 * i];
      double* tq = &P.t[3 * i];
      f[0] += f0; f[1] += f1; f[2] += f2;
      tq[0] = ri * (tq[0] + t0); tq[1] = ri * (tq[1] + t1); tq[2] = ri * (tq[2] + t2);
    }
    double ws[6][3] = {};
    law.wall_pass(fp, i0, i1, ws, with_virial ? &chunk_virial_[12 * c + 6] : nullptr);
    // Gravity, fused with the next step's kick and drift (the same operations, in the
    // same order, as integrate()).
    if (then_integrate) chunk_disp_[c] = gravity_kick_drift<true, true>(P, L, i0, i1, g, kick, dt);
    else gravity_kick_drift<true, false>(P, L, i0, i1, g, kick, dt);
    std::copy(&ws[0][0], &ws[0][0] + 18, &chunk_wall_[c * 18]);
  };

  if (T == 1) {
    for (std::size_t c = 0; c < nchunks; ++c) {
      pair_part(c);
      rest_part(c);
    }
    return;
  }
  // Threads work in pairs on contiguous segments of chunks, one upwards from the bottom of
  // the segment, the other downwards from its top, each claiming chunk after chunk until
  // they meet: however the chunks differ in cost (the dense bottom of a settling bed, the
  // dilute top) and whichever thread the system delays, both finish within about one
  // chunk of each other. The upward thread does the rest of each chunk right after its
  // pair pass; the downward one as soon as the pair passes it depends on are its own,
  // and the rest of its last chunks once the upward thread has passed them. Waits only
  // go to lower chunks, whose pair passes never wait: no deadlock. With more than two
  // threads the segments (one per pair) are split by measured cost, the segment's bottom
  // chunks that depend on the segment below done last.
  const bool timed = T > 2;
  using Clock = std::chrono::steady_clock;
  // Work times (waits excluded) go to chunk_time_[2c] and [2c + 1]: the pair pass and the
  // rest of a chunk may run on different threads at the same time.
  auto run = [&](std::size_t c, bool with_pair, bool with_rest) {
    Clock::time_point t0;
    if (with_pair) {
      if (timed) t0 = Clock::now();
      pair_part(c);
      if (timed) chunk_time_[2 * c] = std::chrono::duration<double>(Clock::now() - t0).count();
    }
    if (with_rest) {
      wait_deps(c);
      if (timed) t0 = Clock::now();
      rest_part(c);
      if (timed) chunk_time_[2 * c + 1] = std::chrono::duration<double>(Clock::now() - t0).count();
    }
  };
  auto claim = [&](std::size_t c) { return ThreadSync::take(sync.chunk(c).claim, pass); };
  const std::size_t lo = balanced_split(chunk_cost_, nchunks, T, t & ~std::size_t{1});
  const std::size_t hi = balanced_split(chunk_cost_, nchunks, T, std::min(T, (t | 1) + 1));
  if (lo == hi) return;
  // Rests of the downward thread's chunks left when the two meet are shared the same way.
  auto claim_rest = [&](std::size_t c) { return ThreadSync::take(sync.chunk(c).rest_claim, pass); };
  if (t % 2 == 0) {
    std::size_t c = lo;
    for (; c < hi && claim(c); ++c) run(c, true, L.chunk_dep[c] >= lo);
    for (std::size_t d = c; d < hi && claim_rest(d); ++d) run(d, false, true);
    for (std::size_t d = lo; d < c; ++d)
      if (L.chunk_dep[d] < lo) run(d, false, true);
  } else {
    std::size_t next_rest = hi;  // the rests of chunks [next_rest, hi) are taken
    std::size_t c = hi;
    for (; c > lo && claim(c - 1); --c) {
      run(c - 1, true, false);
      while (next_rest > c - 1 && L.chunk_dep[next_rest - 1] >= c - 1 && claim_rest(next_rest - 1)) run(--next_rest, false, true);
    }
    while (next_rest > c && claim_rest(next_rest - 1)) run(--next_rest, false, true);
  }
}

void Simulation::end_force_pass() {
  const std::size_t nchunks = force_chunks();
  if (pass_.team > 2) {  // segments by cost (see force_pass_share)
    const bool first = chunk_cost_.empty();
    chunk_cost_.resize(nchunks);
    for (std::size_t c = 0; c < nchunks; ++c) {
      // Smoothed over a few passes; a chunk interrupted by the system counts little.
      const double m = chunk_time_[2 * c] + chunk_time_[2 * c + 1];
      chunk_cost_[c] = first ? m : 0.75 * chunk_cost_[c] + 0.25 * std::min(m, 4.0 * chunk_cost_[c]);
    }
  }
  if (pass_.integrate) finish_integrate();
  for (int w = 0; w < 6; ++w) wall_force_[w].setZero();
  for (std::size_t c = 0; c < nchunks; ++c)
    for (int w = 0; w < 6; ++w)
      for (int a = 0; a < 3; ++a) wall_force_[w][a] += chunk_wall_[c * 18 + 3 * w + a];
  if (pass_.virial) {
    virial_pairs_.fill(0.0);
    virial_walls_.fill(0.0);
    for (std::size_t c = 0; c < nchunks; ++c)
      for (int k = 0; k < 6; ++k) {
        virial_pairs_[k] += chunk_virial_[12 * c + k];
        virial_walls_[k] += chunk_virial_[12 * c + 6 + k];
      }
  }
}

void Simulation::compute_forces(bool update, bool then_integrate) {
  begin_force_pass(update, then_integrate);
#pragma omp parallel if (force_chunks() > 1)
  {
    const TeamSlot team = team_slot();
    force_pass_share(team.index, team.size);
  }
  end_force_pass();
}

void Simulation::finish_integrate() {
  double dmax = 0.0;
  for (double d : chunk_disp_) dmax = std::max(dmax, d);
  const double half = 0.5 * skin_;
  need_rebuild_ = dmax > half * half;
  started_ = true;
}

void Simulation::integrate() {
  const std::size_t n = p_.n;
  const std::size_t kChunk = force_chunk_size(n);
  const std::size_t nchunks = force_chunks();
  chunk_disp_.assign(nchunks, 0.0);
  // Leap-frog, Eq. 2.19: v_{n+1/2} = v_{n−1/2} + F_n/m Δt; r_{n+1} = r_n + v_{n+1/2} Δt.
  // The velocities given at t = 0 are full-step values: the first kick is a half kick.
  const double kick = started_ ? dt_ : 0.5 * dt_;
  const double dt = dt_;
  Particles& P = p_;
  const NeighborList& L = list_;
#pragma omp parallel for schedule(static, 1) if (nchunks > 1)
  for (std::size_t c = 0; c < nchunks; ++c)
    chunk_disp_[c] = gravity_kick_drift<false, true>(P, L, c * kChunk, std::min(n, (c + 1) * kChunk), cfg_.gravity, kick, dt);
  finish_integrate();
}

void Simulation::grow_radii() {
  // Radii of step step_+1; the table is rebuilt because the search distances changed.
  const double frac = cfg_.growth_start + (1.0 - cfg_.growth_start) * static_cast<double>(step_ + 1) /
                                              static_cast<double>(cfg_.growth_steps);
  for (std::size_t i = 0; i < p_.n; ++i) p_.radius[i] = step_ + 1 >= cfg_.growth_steps ? final_radius_[i] : frac * final_radius_[i];
  need_rebuild_ = true;
}

void Simulation::step(std::uint64_t n) {
  if (n == 0) return;
  integrate();
  for (std::uint64_t s = 0; s < n;) {
    if (step_ < cfg_.growth_steps) grow_radii();
    if (need_rebuild_) rebuild();
    // The steps up to the next rebuild share one parallel region: a step costs two
    // barriers of our own (see ThreadSync) instead of a fork and a join, whatever
    // OMP_WAIT_POLICY says. The book-keeping between passes is serial.
    // The last step of a batch stops at F_{n+1} so that the state can be read consistently.
    begin_force_pass(true, s + 1 < n);
    bool more = true;
#pragma omp parallel if (force_chunks() > 1)
    {
      const TeamSlot team = team_slot();
      const std::size_t T = team.size, t = team.index;
      while (more) {
        force_pass_share(t, T);
        sync_->barrier(T);
        if (t == 0) {
          end_force_pass();
          ++step_;
          time_ = static_cast<double>(step_) * dt_;
          ++s;
          more = s < n && !need_rebuild_ && step_ >= cfg_.growth_steps;
          if (more) begin_force_pass(true, s + 1 < n);
        }
        sync_->barrier(T);
      }
    }
  }
}

Vec3 Simulation::velocity(std::size_t i) const {
  if (!started_) return {p_.v[3 * i], p_.v[3 * i + 1], p_.v[3 * i + 2]};
  const double h = 0.5 * dt_ * p_.inv_mass[i];
  return {p_.v[3 * i] + h * p_.f[3 * i], p_.v[3 * i + 1] + h * p_.f[3 * i + 1], p_.v[3 * i + 2] + h * p_.f[3 * i + 2]};
}

Vec3 Simulation::angular_velocity(std::size_t i) const {
  if (!started_) return {p_.w[3 * i], p_.w[3 * i + 1], p_.w[3 * i + 2]};
  const double h = 0.5 * dt_ * p_.inv_inertia[i];
  return {p_.w[3 * i] + h * p_.t[3 * i], p_.w[3 * i + 1] + h * p_.t[3 * i + 1], p_.w[3 * i + 2] + h * p_.t[3 * i + 2]};
}

Vec3 Simulation::force(std::size_t i) const {
  return {p_.f[3 * i], p_.f[3 * i + 1], p_.f[3 * i + 2]};
}

Vec3 Simulation::torque(std::size_t i) const {
  return {p_.t[3 * i], p_.t[3 * i + 1], p_.t[3 * i + 2]};
}

Stats Simulation::stats() const {
  Stats s;
  s.time = time_;
  s.step = step_;
  for (std::size_t i = 0; i < p_.n; ++i) {
    const Vec3 v = velocity(i), w = angular_velocity(i);
    s.kinetic += 0.5 * p_.mass[i] * v.squaredNorm();
    s.rotational += 0.5 * (1.0 / p_.inv_inertia[i]) * w.squaredNorm();
    s.potential_gravity -= p_.mass[i] * (cfg_.gravity.x() * p_.x[3 * i] + cfg_.gravity.y() * p_.x[3 * i + 1] +
                                         cfg_.gravity.z() * p_.x[3 * i + 2]);
    for (std::uint32_t q = list_.first[i]; q < list_.first[i + 1]; ++q) {
      const std::uint32_t j = list_.partner[q];
      const double d2 = centre_distance_sq(i, q);
      const double rs = p_.radius[i] + p_.radius[j];
      if (d2 < rs * rs) ++s.contacts;
    }
    for (int w = 0; w < 6; ++w) {
      if (!box_.wall[w]) continue;
      const int a = w / 2;
      const double dist = w % 2 == 0 ? p_.x[3 * i + a] - box_.lo[a] : box_.hi[a] - p_.x[3 * i + a];
      if (dist < p_.radius[i]) ++s.wall_contacts;
    }
  }
  s.coordination = p_.n ? 2.0 * static_cast<double>(s.contacts) / static_cast<double>(p_.n) : 0.0;
  s.volume = box_.len[0] * box_.len[1] * box_.len[2];
  s.virial_pairs = virial_pairs_;
  s.virial_walls = virial_walls_;
  s.pressure_tensor = pressure_tensor();
  s.pressure = (s.pressure_tensor[0] + s.pressure_tensor[1] + s.pressure_tensor[2]) / 3.0;
  s.wall_force = wall_force_;
  s.neighbor_builds = list_.builds;
  s.neighbor_pairs = list_.pairs();
  return s;
}

std::array<double, 6> Simulation::pressure_tensor() const {
  // Kinetic part about the mass-averaged velocity, then the contact virial measured by the
  // pass that computed the current forces (see Stats).
  double mtot = 0.0;
  Vec3 mom = Vec3::Zero();
  for (std::size_t i = 0; i < p_.n; ++i) {
    mtot += p_.mass[i];
    mom += p_.mass[i] * velocity(i);
  }
  const Vec3 vcm = mtot > 0.0 ? Vec3(mom / mtot) : Vec3::Zero();
  std::array<double, 6> kin{};
  for (std::size_t i = 0; i < p_.n; ++i) {
    const Vec3 c = velocity(i) - vcm;
    const double m = p_.mass[i];
    kin[0] += m * c.x() * c.x();
    kin[1] += m * c.y() * c.y();
    kin[2] += m * c.z() * c.z();
    kin[3] += m * c.x() * c.y();
    kin[4] += m * c.x() * c.z();
    kin[5] += m * c.y() * c.z();
  }
  const double volume = box_.len[0] * box_.len[1] * box_.len[2];
  std::array<double, 6> p{};
  for (int k = 0; k < 6; ++k) p[k] = (kin[k] + virial_pairs_[k] + virial_walls_[k]) / volume;
  return p;
}

std::vector<Vec3> simple_cubic_lattice(const Vec3& lo, double a, int nx, int ny, int nz) {
  std::vector<Vec3> out;
  out.reserve(static_cast<std::size_t>(nx) * ny * nz);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) out.emplace_back(lo.x() + (i + 0.5) * a, lo.y() + (j + 0.5) * a, lo.z() + (k + 0.5) * a);
  return out;
}

std::vector<Vec3> random_positions(const Vec3& lo, const Vec3& hi, double r, std::size_t count, std::uint64_t seed) {
  core::Rng rng(seed);
  std::vector<Vec3> out;
  out.reserve(count);
  // Candidates are tested against the spheres already placed in the 27 cells around them
  // (cells at least 2r wide): the same accept/reject rule as testing every placed sphere,
  // so the same draws give the same positions, in O(N) instead of O(N²).
  std::array<int, 3> cells{};
  std::array<double, 3> cell_len{};
  for (int a = 0; a < 3; ++a) {
    const double span = std::max(0.0, hi[a] - lo[a]);
    cells[std::size_t(a)] = std::clamp(int(span / (2.0 * r)), 1, 256);
    cell_len[std::size_t(a)] = span > 0 ? span / cells[std::size_t(a)] : 1.0;
  }
  auto cell_of = [&](const Vec3& x, int a) {
    return std::clamp(int((x[a] - lo[a]) / cell_len[std::size_t(a)]), 0, cells[std::size_t(a)] - 1);
  };
  const std::size_t cell_count = std::size_t(cells[0]) * std::size_t(cells[1]) * std::size_t(cells[2]);
  std::vector<std::vector<std::uint32_t>> grid(cell_count);
  auto index = [&](int i, int j, int k) { return (std::size_t(k) * std::size_t(cells[1]) + std::size_t(j)) * std::size_t(cells[0]) + std::size_t(i); };
  const std::size_t max_tries = 1000 * (count + 10);
  std::size_t tries = 0;
  while (out.size() < count) {
    if (++tries > max_tries)
      throw Error("dem: could not place " + std::to_string(count) + " spheres of radius " + num(r) +
                  " m at random without overlap (placed " + std::to_string(out.size()) + "); use a larger box or a lattice");
    Vec3 x;
    for (int a = 0; a < 3; ++a) x[a] = rng.uniform(lo[a] + r, hi[a] - r);
    const int ci = cell_of(x, 0), cj = cell_of(x, 1), ck = cell_of(x, 2);
    bool ok = true;
    for (int k = std::max(0, ck - 1); ok && k <= std::min(cells[2] - 1, ck + 1); ++k)
      for (int j = std::max(0, cj - 1); ok && j <= std::min(cells[1] - 1, cj + 1); ++j)
        for (int i = std::max(0, ci - 1); ok && i <= std::min(cells[0] - 1, ci + 1); ++i)
          for (const std::uint32_t q : grid[index(i, j, k)])
            if ((x - out[q]).squaredNorm() < 4.0 * r * r) {
              ok = false;
              break;
            }
    if (ok) {
      grid[index(ci, cj, ck)].push_back(std::uint32_t(out.size()));
      out.push_back(x);
    }
  }
  return out;
}

}  // namespace grainflow::dem
