// Whole-engine tests of the DEM simulation (seed 000 ch. 2–4): restitution of a binary
// collision, time step, energy conservation, neighbour-search equivalence (§4.1), thread
// independence, bitwise restart, input validation, and the LAMMPS reference collision.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <numbers>
#include <sstream>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "engine/core/error.hpp"
#include "engine/core/rng.hpp"
#include "engine/dem/simulation.hpp"
#include "engine/io/archive.hpp"
#include "engine/dem/time_step.hpp"

using namespace grainflow;
using namespace grainflow::dem;

namespace {

constexpr double kD = 1e-3;
constexpr double kRho = 2500.0;

double sphere_mass(double r, double rho) { return 4.0 / 3.0 * std::numbers::pi * r * r * r * rho; }

// The reference benchmark system (tests/bench, /work/shared/bench/dem): Hooke + history.
Config bench_config(int nx, int ny, int nz, NeighborMethod nm = NeighborMethod::ChainCells) {
  Config c;
  const double a = 1.02 * kD;
  c.box.lo = Vec3::Zero();
  c.box.hi = Vec3(nx * a, ny * a, 1.25 * nz * a);
  c.model = {NormalKind::Hooke, TangentialKind::History, CohesionKind::None};
  GroupConfig g;
  g.radius = 0.5 * kD;
  g.density = kRho;
  g.contact.k1 = 100.0;
  g.contact.kt = 2.0 / 7.0 * 100.0;
  g.contact.gamma_n = 828.628;
  g.contact.gamma_t = 0.5 * 828.628;
  g.contact.mu = 0.5;
  c.groups = {g};
  c.dt = 5e-6;
  c.skin = 0.2 * kD;
  c.neighbor = nm;
  const auto pos = simple_cubic_lattice(Vec3::Zero(), a, nx, ny, nz);
  for (std::size_t i = 0; i < pos.size(); ++i) {
    ParticleInit p;
    p.x = pos[i];
    const double id = static_cast<double>(i + 1);
    p.v = Vec3(0.1 * std::sin(12.9898 * id), 0.1 * std::sin(78.2330 * id), 0.1 * std::sin(37.7190 * id));
    c.particles.push_back(p);
  }
  return c;
}

// Walton models, frictional, with seeded random velocities.
Config walton_box(int nx, int ny, int nz, double e, double mu, std::uint64_t seed) {
  Config c;
  const double a = 1.05 * kD;
  c.box.lo = Vec3::Zero();
  c.box.hi = Vec3(nx * a, ny * a, 1.5 * nz * a);
  c.model = {NormalKind::Walton, mu > 0 ? TangentialKind::Walton : TangentialKind::None, CohesionKind::None};
  GroupConfig g;
  g.radius = 0.5 * kD;
  g.density = kRho;
  g.contact.k1 = 200.0;
  g.contact.e = e;
  g.contact.kt = 2.0 / 7.0 * 200.0;
  g.contact.mu = mu;
  c.groups = {g};
  c.steps_per_collision = 50;
  c.skin = 0.2 * kD;
  core::Rng rng(seed);
  for (const Vec3& x : simple_cubic_lattice(Vec3::Zero(), a, nx, ny, nz)) {
    ParticleInit p;
    p.x = x;
    p.v = Vec3(rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1));
    c.particles.push_back(p);
  }
  return c;
}

Config two_spheres(double e, double v, NormalKind nk = NormalKind::Walton) {
  Config c;
  c.box.lo = Vec3(-0.01, -0.01, -0.01);
  c.box.hi = Vec3(0.01, 0.01, 0.01);
  c.gravity = Vec3::Zero();
  c.model = {nk, TangentialKind::None, CohesionKind::None};
  GroupConfig g;
  g.radius = 0.5 * kD;
  g.density = kRho;
  g.contact.k1 = 100.0;
  g.contact.e = e;
  c.groups = {g};
  c.steps_per_collision = 50;
  ParticleInit a, b;
  a.x = Vec3(-0.6 * kD, 0, 0);
  a.v = Vec3(v, 0, 0);
  b.x = Vec3(0.6 * kD, 0, 0);
  b.v = Vec3(-v, 0, 0);
  c.particles = {a, b};
  return c;
}

bool same_state(const Simulation& a, const Simulation& b) {
  return a.particles().x == b.particles().x && a.particles().v == b.particles().v && a.particles().w == b.particles().w;
}

}  // namespace

TEST(DemTimeStep, DefaultFollowsEq223) {
  Simulation s(two_spheres(0.8, 0.1));
  const double m = sphere_mass(0.5 * kD, kRho);
  EXPECT_DOUBLE_EQ(s.dt(), walton_time_step(m, 100.0, 0.8, 50));
  EXPECT_NEAR(s.dt(), std::numbers::pi * 0.8 * std::sqrt(m / 200.0) / 50.0, 1e-20);
}

TEST(DemTimeStep, IsTheChosenNormalModelsCollisionTimeOverN) {
  const double m = sphere_mass(0.5 * kD, kRho);
  const double mu = m * m / (m + m);  // the pair: a shorter collision than at a wall (μ = m)
  for (const NormalKind nk : {NormalKind::Walton, NormalKind::Hooke}) {
    Config c = two_spheres(0.8, 0.1, nk);
    c.steps_per_collision = 40;
    const Simulation s(c);
    const double tc = visit_model(nk, [&]<class N>(std::type_identity<N>) {
      return N::collision_time(c.groups[0].contact, mu, mu);
    });
    EXPECT_EQ(s.dt(), tc / 40) << model_name(nk);
    EXPECT_EQ(s.dt(), collision_time(c.model, c.groups[0].contact, mu, mu) / 40) << model_name(nk);
  }
  // Hooke against π/ω_d, ω_d² = kn/μ − γn²/4, with γn derived from e = 0.8.
  const Simulation s(two_spheres(0.8, 0.1, NormalKind::Hooke));
  const double gn = hooke_gamma_from_restitution(100.0, 0.8, mu);
  EXPECT_DOUBLE_EQ(s.dt(), std::numbers::pi / std::sqrt(100.0 / mu - 0.25 * gn * gn) / 50);
}

TEST(DemRestitution, BinaryHeadOnCollisionGivesSqrtK1OverK2) {
  for (double e : {0.5, 0.8, 0.95, 1.0}) {
    Simulation s(two_spheres(e, 0.05));
    const double v_before = s.velocity(0).x() - s.velocity(1).x();
    s.step(static_cast<std::uint64_t>(0.2 * kD / 0.05 / s.dt()) + 200);  // approach + contact
    ASSERT_GT(s.position(1).x() - s.position(0).x(), kD) << "still in contact";
    const double v_after = s.velocity(0).x() - s.velocity(1).x();
    EXPECT_NEAR(-v_after / v_before, e, 1e-3) << "e = " << e;
    EXPECT_NEAR(s.velocity(0).x() + s.velocity(1).x(), 0.0, 1e-15);  // momentum
  }
}

TEST(DemLammps, ObliqueHookeCollisionMatchesLammpsReference) {
  // tests/data/dem/lammps_oblique_hooke.in produced the dump read here (LAMMPS 29 Sep 2021).
  std::ifstream in(std::string(GRAINFLOW_TEST_DATA) + "/dem/lammps_oblique_hooke.dump");
  ASSERT_TRUE(in) << "missing reference dump";
  Config c;
  c.box.lo = Vec3(-0.005, -0.005, -0.005);
  c.box.hi = Vec3(0.005, 0.005, 0.005);
  c.gravity = Vec3::Zero();
  c.model = {NormalKind::Hooke, TangentialKind::History, CohesionKind::None};
  GroupConfig g;
  g.radius = 0.5e-3;
  g.density = 2500.0;
  g.contact.k1 = 100.0;
  g.contact.kt = 28.571428571428573;
  g.contact.gamma_n = 828.628;
  g.contact.gamma_t = 414.314;
  g.contact.mu = 0.5;
  c.groups = {g};
  c.dt = 5e-6;
  c.skin = 0.2e-3;
  ParticleInit a, b;
  a.x = Vec3(0, 0, 0);
  a.v = Vec3(0.2, 0, 0.01);
  a.omega = Vec3(0, 0, 800);
  b.x = Vec3(0.00102, 0.00045, 0.0001);
  b.v = Vec3(-0.05, -0.02, 0);
  b.omega = Vec3(10, -20, 0);
  c.particles = {a, b};
  Simulation s(c);
  // Tolerances relative to each quantity's scale (rounding differs: LAMMPS kicks in two
  // half steps, we kick once; the contact is not chaotic over 400 steps).
  const double tol_x = 1e-14, tol_v = 1e-12, tol_f = 1e-12, tol_w = 1e-9, tol_t = 1e-17;
  std::string line;
  int frames = 0, touching = 0;
  double max_dx = 0, max_dv = 0, max_df = 0;
  while (std::getline(in, line)) {
    if (line != "ITEM: TIMESTEP") continue;
    std::uint64_t step;
    in >> step;
    while (std::getline(in, line) && line.rfind("ITEM: ATOMS", 0) != 0) {
    }
    if (step > s.steps()) s.step(step - s.steps());
    for (int k = 0; k < 2; ++k) {
      int id;
      double q[15];
      in >> id;
      for (double& v : q) in >> v;
      const std::size_t i = static_cast<std::size_t>(id - 1);
      const Vec3 x = s.position(i), v = s.velocity(i), f = s.force(i), w = s.angular_velocity(i), t = s.torque(i);
      for (int d = 0; d < 3; ++d) {
        EXPECT_NEAR(x[d], q[d], tol_x) << "step " << step << " id " << id << " x" << d;
        EXPECT_NEAR(v[d], q[3 + d], tol_v) << "step " << step << " id " << id << " v" << d;
        EXPECT_NEAR(f[d], q[6 + d], tol_f) << "step " << step << " id " << id << " f" << d;
        EXPECT_NEAR(w[d], q[9 + d], tol_w) << "step " << step << " id " << id << " omega" << d;
        EXPECT_NEAR(t[d], q[12 + d], tol_t) << "step " << step << " id " << id << " torque" << d;
        max_dx = std::max(max_dx, std::fabs(x[d] - q[d]));
        max_dv = std::max(max_dv, std::fabs(v[d] - q[3 + d]));
        max_df = std::max(max_df, std::fabs(f[d] - q[6 + d]));
      }
      if (k == 0 && q[6] != 0.0) ++touching;
    }
    ++frames;
  }
  EXPECT_EQ(frames, 41);
  EXPECT_GE(touching, 4);  // the reference really contains the contact
  std::printf("max |dx| %.3g m, |dv| %.3g m/s, |df| %.3g N\n", max_dx, max_dv, max_df);
}

// A sparse huge box gets a coarse grid (at most a few cells per particle), not 1024³
// cells (8.6 GB, 27 s for two spheres in 10 m): the same pairs and bits as the N² search.
TEST(DemNeighbors, ASparseHugeBoxGetsACoarseGridWithTheSameTrajectory) {
  for (bool periodic : {false, true}) {
    Config c = bench_config(4, 4, 4);
    c.box.hi = Vec3(10.0, 10.0, 10.0);  // 64 spheres in a corner of a 10 m box
    if (periodic) c.box.periodic = {true, true, true};
    Config c2 = c;
    c2.neighbor = NeighborMethod::AllPairs;
    const auto t0 = std::chrono::steady_clock::now();
    Simulation a(c);
    a.step(500);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
    Simulation b(c2);
    b.step(500);
    EXPECT_TRUE(same_state(a, b)) << "periodic = " << periodic;
    EXPECT_EQ(a.neighbors().partner, b.neighbors().partner);
  }
}

TEST(DemNeighbors, ChainCellsAndAllPairsGiveBitwiseIdenticalTrajectories) {
  // Seed 000 §4.1: the two searches must give the same trajectories. 2,000 spheres falling
  // in a closed box (Walton models with friction), plus a periodic variant.
#ifdef _OPENMP
  // Search equivalence does not need threads; one thread keeps the test fast on a loaded
  // machine (thread independence is tested on its own below).
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
#endif
  for (bool periodic : {false, true}) {
    Config c = walton_box(10, 10, 20, 0.8, 0.3, 7);
    if (periodic) c.box.periodic = {true, true, false};
    Config c2 = c;
    c2.neighbor = NeighborMethod::AllPairs;
    Simulation a(c), b(c2);
    a.step(1000);
    b.step(1000);
    EXPECT_TRUE(same_state(a, b)) << "periodic = " << periodic;
    EXPECT_EQ(a.neighbors().partner, b.neighbors().partner);
    EXPECT_EQ(a.neighbors().hist, b.neighbors().hist);
    const Stats st = a.stats();
    EXPECT_GE(st.neighbor_builds, 3u);  // rebuilds happened, history carried over
    EXPECT_GT(st.contacts, 100u);
  }
#ifdef _OPENMP
  omp_set_num_threads(saved);
#endif
}

TEST(DemEnergy, ConservedForElasticFrictionlessSpheres) {
  // e = 1, μ = 0: KE + gravity PE + spring PE is constant up to the leap-frog error,
  // O((ω Δt)²) ≈ (π/n)² per unit of contact energy while contacts last; with n = 50 the
  // bound used is 1e-3 of the initial energy (measured ~1e-4 here).
  Config c = walton_box(6, 6, 6, 1.0, 0.0, 3);
  Simulation s(c);
  const double k1 = 200.0;
  auto energy = [&](Simulation& sim) {
    const Stats st = sim.stats();
    double pe = 0.0;
    for (std::size_t i = 0; i < sim.size(); ++i) {
      for (std::size_t j = i + 1; j < sim.size(); ++j) {
        const double d = sim.radius(i) + sim.radius(j) - (sim.position(i) - sim.position(j)).norm();
        if (d > 0) pe += 0.5 * k1 * d * d;
      }
      for (int a = 0; a < 3; ++a) {
        const double lo = sim.radius(i) - (sim.position(i)[a] - c.box.lo[a]);
        const double hi = sim.radius(i) - (c.box.hi[a] - sim.position(i)[a]);
        if (lo > 0) pe += 0.5 * k1 * lo * lo;
        if (hi > 0) pe += 0.5 * k1 * hi * hi;
      }
    }
    return st.kinetic + st.rotational + st.potential_gravity + pe;
  };
  const double e0 = energy(s);
  double worst = 0.0;
  for (int k = 0; k < 20; ++k) {
    s.step(250);
    worst = std::max(worst, std::fabs(energy(s) - e0));
  }
  const double ke0 = 0.5 * sphere_mass(0.5 * kD, kRho) * 216 * 0.01;  // scale: ~ initial KE
  std::printf("max |E - E0| = %.3g J (E0 = %.6g J, KE scale %.3g J)\n", worst, e0, ke0);
  EXPECT_LT(worst, 1e-3 * std::fabs(e0));
  EXPECT_GT(s.stats().contacts + s.stats().wall_contacts, 0u);
}

#ifdef _OPENMP
namespace {
// The same run with each thread count in turn (the global OpenMP setting is restored).
std::vector<Simulation> run_with_threads(const Config& c, std::uint64_t steps, std::initializer_list<int> threads) {
  const int saved = omp_get_max_threads();
  std::vector<Simulation> runs;
  for (int t : threads) {
    omp_set_num_threads(t);
    runs.emplace_back(c);
    runs.back().step(steps);
  }
  omp_set_num_threads(saved);
  return runs;
}
}  // namespace

TEST(DemParallel, PeriodicWaltonRunIsThreadCountIndependentAcrossForceChunks) {
  // Pairs whose partner lies in a later force chunk go through the gathered pair slots,
  // the others are scattered at once; periodic images add pairs that span the whole index
  // range. 1 to 5 threads must give the same bits: two threads share the chunks from both
  // ends, more split them into segments by measured cost (an odd one out works alone), and
  // more threads than cores make the waits sleep.
  Config c = walton_box(10, 10, 8, 0.8, 0.3, 5);
  c.box.periodic = {true, true, false};
  ASSERT_GE(c.particles.size(), 3 * force_chunk_size(c.particles.size()));
  const std::vector<Simulation> runs = run_with_threads(c, 600, {1, 2, 3, 4, 5});
  const Simulation& a = runs[0];
  std::size_t cross = 0;
  const std::size_t K = force_chunk_size(a.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::uint32_t q = a.neighbors().first[i]; q < a.neighbors().first[i + 1]; ++q)
      cross += a.neighbors().partner[q] / K != i / K;
  EXPECT_GT(cross, 50u);  // the gathered path is exercised
  for (std::size_t r = 1; r < runs.size(); ++r) {
    EXPECT_TRUE(same_state(a, runs[r])) << "threads = " << r + 1;
    EXPECT_EQ(a.neighbors().hist, runs[r].neighbors().hist);
    for (int w = 0; w < 6; ++w) EXPECT_EQ(a.stats().wall_force[w], runs[r].stats().wall_force[w]);
  }
  EXPECT_GT(a.stats().contacts, 50u);
}

TEST(DemParallel, PairsAcrossTheWholeIndexRangeKeepThreadCountIndependence) {
  // Periodic along z with the lattice filling the height: the bottom layer touches the
  // top one, so the top chunks depend on chunk 0 while the chunks below them do not. A
  // thread must then finish chunks out of order (segments of 3+ threads, the meeting of
  // two): every rest done once, after the pair passes it needs.
  Config c = walton_box(10, 10, 16, 0.8, 0.3, 11);
  c.box.periodic = {true, true, true};
  c.box.hi.z() = 16 * 1.05 * kD;
  c.gravity = Vec3::Zero();
  const std::vector<Simulation> runs = run_with_threads(c, 400, {1, 2, 3, 4, 5});
  const auto& dep = runs[0].neighbors().chunk_dep;
  ASSERT_GE(dep.size(), 8u);
  EXPECT_EQ(dep.back(), 0u);               // the top chunk depends on the bottom one
  EXPECT_GE(dep[dep.size() / 2], 2u);      // a middle one does not
  for (std::size_t r = 1; r < runs.size(); ++r) {
    EXPECT_TRUE(same_state(runs[0], runs[r])) << "threads = " << r + 1;
    EXPECT_EQ(runs[0].neighbors().hist, runs[r].neighbors().hist);
  }
  EXPECT_GT(runs[0].stats().contacts, 100u);
}

TEST(DemParallel, OneAndTwoThreadsGiveBitwiseEqualResults) {
  const std::vector<Simulation> runs = run_with_threads(bench_config(10, 10, 8), 800, {1, 2});  // 800 spheres
  const Simulation &a = runs[0], &b = runs[1];
  EXPECT_TRUE(same_state(a, b));
  EXPECT_EQ(a.neighbors().hist, b.neighbors().hist);
  EXPECT_GT(a.stats().contacts, 50u);
}
#endif

TEST(DemLanes, PerTypeParametersGiveTheSameBitsAsSharedOnes) {
  // Contacts are evaluated in SIMD lanes with the parameters shared by the whole batch
  // when every particle–particle (and every particle–wall) type pair has the same ones,
  // else looked up lane by lane. An unused second group with other parameters forces the
  // per-lane look-up: the trajectory must not change by a bit.
  const Config one = bench_config(10, 10, 8);
  Config two = one;
  GroupConfig other = one.groups[0];
  other.contact.mu = 0.3;
  two.groups.push_back(other);
  Simulation a(one), b(two);
  a.step(800);
  b.step(800);
  EXPECT_TRUE(same_state(a, b));
  EXPECT_EQ(a.neighbors().hist, b.neighbors().hist);
  EXPECT_GT(a.stats().contacts, 50u);
  EXPECT_GT(a.stats().wall_contacts, 0u);
}

TEST(DemCheckpoint, RestartContinuesBitForBit) {
  Config c = walton_box(8, 8, 8, 0.7, 0.4, 11);
  Simulation ref(c);
  ref.step(600);
  Simulation s(c);
  s.step(300);
  (void)s.stats();  // a measurement between steps must not perturb the run
  io::ArchiveWriter w;
  s.save_state(w);
  // Restored into a fresh simulation of the same configuration, on another thread count.
  const int threads = thread_count();
  set_thread_count(threads == 1 ? 2 : 1);
  Simulation r(c);
  io::ArchiveReader in(w.bytes(), "state");
  r.load_state(in);
  EXPECT_TRUE(in.at_end());
  EXPECT_EQ(r.steps(), 300u);
  r.step(300);
  set_thread_count(threads);
  EXPECT_TRUE(same_state(ref, r));
  EXPECT_EQ(ref.neighbors().hist, r.neighbors().hist);
  EXPECT_GT(ref.stats().contacts, 0u);
  // Saving the restored state again gives the same bytes.
  {
    Simulation again(c);
    io::ArchiveReader in2(w.bytes(), "state");
    again.load_state(in2);
    io::ArchiveWriter w2;
    again.save_state(w2);
    EXPECT_EQ(w.bytes(), w2.bytes());
  }
  // A truncated state is refused, naming what is missing.
  {
    Simulation t(c);
    io::ArchiveReader cut(std::string_view(w.bytes()).substr(0, w.bytes().size() / 2), "state");
    try {
      t.load_state(cut);
      ADD_FAILURE() << "a truncated state was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
    }
  }
  // So is a state saved under another configuration.
  {
    Config other = c;
    other.gravity = Vec3(0, 0, -1.0);
    Simulation o(other);
    io::ArchiveReader in3(w.bytes(), "state");
    try {
      o.load_state(in3);
      ADD_FAILURE() << "a state of another configuration was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("configuration"), std::string::npos) << e.what();
    }
  }
}

namespace {
void expect_error(const Config& c, const std::string& fragment) {
  try {
    Simulation s(c);
    ADD_FAILURE() << "no error, expected one mentioning \"" << fragment << "\"";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}
}  // namespace

TEST(DemValidation, BadInputGivesClearErrors) {
  Config c = two_spheres(0.8, 0.1);
  Config bad = c;
  bad.particles[1].x = Vec3(0.2 * kD, 0, 0);
  expect_error(bad, "overlap");
  bad = c;
  bad.dt = 1e-3;
  expect_error(bad, "stability limit");
  bad = c;
  bad.groups[0].contact.k1 = 0.0;
  expect_error(bad, "k1");
  bad = c;
  bad.groups[0].contact.k1 = -5.0;
  expect_error(bad, "k1");
  bad = c;
  bad.groups[0].contact.e = 0.0;
  expect_error(bad, "(0, 1]");
  bad = c;
  bad.groups[0].contact.e = 1.2;
  expect_error(bad, "(0, 1]");
  bad = c;
  bad.particles[0].x = Vec3(0.02, 0, 0);
  expect_error(bad, "outside the box");
  bad = c;
  bad.particles[0].x = Vec3(-0.01 + 0.2 * kD, 0, 0);
  expect_error(bad, "overlaps the wall");
  bad = c;
  bad.model.tangential = TangentialKind::Walton;
  bad.groups[0].contact.kt = 0.0;
  expect_error(bad, "kt");
  EXPECT_THROW(normal_kind_from_name("hertz"), Error);
}

TEST(DemWalls, CouetteWallDragsParticleAndReportsForces) {
  // A sphere resting on a bottom wall moving at +x is dragged along by friction; the
  // force reported on the bottom wall balances its weight.
  // Hooke + history (damped) so the sphere comes to rest on the wall; Walton's latching
  // spring has no damping of small oscillations on its unloading line.
  Config c = two_spheres(0.8, 0.0, NormalKind::Hooke);
  c.model.tangential = TangentialKind::History;
  c.groups[0].contact.kt = 2.0 / 7.0 * 100.0;
  c.groups[0].contact.mu = 0.5;
  c.gravity = Vec3(0, 0, -9.81);
  c.particles = {c.particles[0]};
  c.particles[0].x = Vec3(0, 0, -0.01 + 0.5 * kD);
  c.box.wall_velocity[4] = Vec3(0.01, 0, 0);
  Simulation s(c);
  s.step(20000);
  EXPECT_GT(s.velocity(0).x(), 0.001);
  const Stats st = s.stats();
  const double w = sphere_mass(0.5 * kD, kRho) * 9.81;
  EXPECT_NEAR(st.wall_force[4].z(), -w, 0.05 * w);
  EXPECT_EQ(st.wall_contacts, 1u);
}
