// The DEM pressure tensor (Stats::pressure_tensor): the contact virial of a pair against
// r ⊗ F of the forces the engine applied (inside the box and across a periodic boundary),
// the wall contacts' share, an ideal gas (kinetic part only, about the mean velocity),
// a settled column (W_zz = Σ m g z), thread-count independence, checkpoints, and LAMMPS's
// compute pressure of a dense periodic run (tests/data/dem/lammps_pressure).
#include <gtest/gtest.h>

#include <array>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <numbers>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <Eigen/Geometry>

#include "engine/core/rng.hpp"
#include "engine/dem/simulation.hpp"
#include "engine/io/archive.hpp"

using namespace grainflow;
using namespace grainflow::dem;

namespace {

constexpr double kR = 0.5e-3;

// r ⊗ F symmetrised, xx yy zz xy xz yz (the documented definition, written out here).
std::array<double, 6> sym_outer(const Vec3& r, const Vec3& f) {
  return {r.x() * f.x(), r.y() * f.y(), r.z() * f.z(), 0.5 * (r.x() * f.y() + r.y() * f.x()),
          0.5 * (r.x() * f.z() + r.z() * f.x()), 0.5 * (r.y() * f.z() + r.z() * f.y())};
}

// Σ m (v − V)(v − V) over the particles, V the mass-averaged velocity.
std::array<double, 6> kinetic_tensor(const Simulation& s) {
  double m = 0.0;
  Vec3 p = Vec3::Zero();
  for (std::size_t i = 0; i < s.size(); ++i) {
    m += s.mass(i);
    p += s.mass(i) * s.velocity(i);
  }
  const Vec3 V = p / m;
  std::array<double, 6> k{};
  for (std::size_t i = 0; i < s.size(); ++i) {
    const Vec3 c = s.velocity(i) - V;
    const auto t = sym_outer(c, s.mass(i) * c);
    for (int a = 0; a < 6; ++a) k[a] += t[a];
  }
  return k;
}

// Two frictional Hooke spheres approaching obliquely with spin, in a large box without
// gravity; x0 and x1 their centres, the box periodic along x when asked.
Config pair_config(const Vec3& x0, const Vec3& x1, const Vec3& v0, const Vec3& v1, bool periodic_x,
                   double gamma_n = 500.0) {
  Config c;
  c.box.lo = Vec3(0, 0, 0);
  c.box.hi = Vec3(0.01, 0.01, 0.01);
  c.box.periodic = {periodic_x, false, false};
  c.gravity = Vec3::Zero();
  c.model = {NormalKind::Hooke, TangentialKind::History, CohesionKind::None};
  GroupConfig g;
  g.radius = kR;
  g.density = 2500.0;
  g.contact.k1 = 100.0;
  g.contact.kt = 2.0 / 7.0 * 100.0;
  g.contact.gamma_n = gamma_n;
  g.contact.gamma_t = 0.5 * gamma_n;
  g.contact.mu = 0.5;
  c.groups = {g};
  c.dt = 2e-6;
  ParticleInit a, b;
  a.x = x0;
  a.v = v0;
  a.omega = Vec3(30.0, -50.0, 80.0);
  b.x = x1;
  b.v = v1;
  b.omega = Vec3(-20.0, 10.0, 40.0);
  c.particles = {a, b};
  return c;
}

// Steps until the pair is in contact, some way into it (tangential force built up).
void step_into_contact(Simulation& s) {
  for (int k = 0; k < 20000 && s.stats().contacts == 0; ++k) s.step(10);
  ASSERT_EQ(s.stats().contacts, 1u);
  s.step(40);
  ASSERT_EQ(s.stats().contacts, 1u);
}

void expect_pair_virial(const Simulation& s, const Vec3& r01) {
  const Stats st = s.stats();
  const Vec3 f0 = s.force(0);  // the pair's force on particle 0 (no gravity, no wall in reach)
  ASSERT_GT(f0.norm(), 0.0);
  // A tangential force is present: r ⊗ F is not symmetric, the symmetrised part is reported.
  EXPECT_GT(r01.cross(f0).norm(), 1e-3 * r01.norm() * f0.norm());
  const auto w = sym_outer(r01, f0);
  const auto k = kinetic_tensor(s);
  const double scale = std::abs(r01.dot(f0));
  for (int a = 0; a < 6; ++a) {
    EXPECT_NEAR(st.virial_pairs[a], w[a], 1e-12 * scale) << "component " << a;
    EXPECT_EQ(st.virial_walls[a], 0.0);
    const double p = (k[a] + w[a]) / st.volume;
    EXPECT_NEAR(st.pressure_tensor[a], p, 1e-12 * std::abs(scale / st.volume)) << "component " << a;
  }
  EXPECT_NEAR(st.volume, 1e-6, 1e-18);
  EXPECT_DOUBLE_EQ(st.pressure, (st.pressure_tensor[0] + st.pressure_tensor[1] + st.pressure_tensor[2]) / 3.0);
  // The overlap pushes the centres apart: the normal virial is positive, W_trace = r·F.
  EXPECT_GT(r01.dot(f0), 0.0);
}

}  // namespace

TEST(DemPressure, TwoSpheresInContactGiveTheirExactVirial) {
  const Vec3 x0(0.004, 0.005, 0.0052), x1(0.0052, 0.0054, 0.0047);
  Simulation s(pair_config(x0, x1, Vec3(0.05, 0.02, -0.01), Vec3(-0.06, -0.01, 0.02), false));
  step_into_contact(s);
  expect_pair_virial(s, s.position(0) - s.position(1));
  // The same through the normal spring alone: W_trace = r·F = |r| (kn δ + damping), the
  // damping term small at this approach speed.
  const Vec3 r = s.position(0) - s.position(1);
  const double delta = 2.0 * kR - r.norm();
  EXPECT_GT(delta, 0.0);
  const Stats st = s.stats();
  const double trace = st.virial_pairs[0] + st.virial_pairs[1] + st.virial_pairs[2];
  EXPECT_NEAR(trace, r.norm() * 100.0 * delta, 0.5 * r.norm() * 100.0 * delta);
}

TEST(DemPressure, APairAcrossAPeriodicBoundaryUsesTheMinimumImage) {
  // Particle 0 near x = Lx, particle 1 near x = 0, approaching through the boundary: the
  // separation the force acts across is x0 − x1 − Lx (about −2R along x), not ≈ Lx.
  const double L = 0.01;
  Simulation s(pair_config(Vec3(L - 0.6e-3, 0.005, 0.005), Vec3(0.45e-3, 0.0052, 0.0049), Vec3(0.05, 0.01, 0.0),
                           Vec3(-0.05, -0.01, 0.01), true));
  step_into_contact(s);
  Vec3 r = s.position(0) - s.position(1);
  r.x() -= std::round(r.x() / L) * L;
  ASSERT_LT(r.norm(), 2.0 * kR);
  expect_pair_virial(s, r);
}

TEST(DemPressure, AWallContactCountsWithTheBranchToItsFoot) {
  // One sphere settling on the floor under gravity: W = (x − foot) ⊗ F_wall with the foot
  // on z = lo, F_wall = −(force on the wall); at rest W_zz = m g z, and gravity adds nothing.
  Config c = pair_config(Vec3(0.005, 0.005, 0.0007), Vec3(0.008, 0.008, 0.008), Vec3(0.01, 0.0, 0.0), Vec3::Zero(), false,
                         1e4);
  c.particles.pop_back();
  c.gravity = Vec3(0, 0, -9.81);
  c.box.lo.z() = -0.001;
  Simulation s(c);
  s.step(20000);  // 0.04 s: settled (γn = 10⁴/s: e ≈ 0.1)
  const Stats st = s.stats();
  ASSERT_EQ(st.wall_contacts, 1u);
  const Vec3 fw = -st.wall_force[4];
  const Vec3 r(0.0, 0.0, s.position(0).z() - c.box.lo.z());
  const auto w = sym_outer(r, fw);
  for (int a = 0; a < 6; ++a) {
    EXPECT_NEAR(st.virial_walls[a], w[a], 1e-12 * std::abs(w[2])) << "component " << a;
    EXPECT_EQ(st.virial_pairs[a], 0.0);
  }
  const double mgz = s.mass(0) * 9.81 * r.z();
  EXPECT_NEAR(st.pressure_tensor[2] * st.volume, mgz, 1e-6 * mgz);
}

TEST(DemPressure, ASettledColumnCarriesItsWeightTimesItsHeight) {
  // Three spheres stacked on the floor: per particle, contact forces balance gravity, so
  // Σ_contacts r ⊗ F (pairs and the floor) = Σ m g (z_i − z_lo) in zz. Without the wall
  // contact only the pairs' 3 m g R·(…) would remain.
  Config c = pair_config(Vec3(0.005, 0.005, 0.0006), Vec3(0.005, 0.005, 0.0017), Vec3::Zero(), Vec3::Zero(), false,
                         1e4);
  ParticleInit top = c.particles[1];
  top.x.z() = 0.0028;
  top.omega = Vec3::Zero();
  c.particles[0].omega = c.particles[1].omega = Vec3::Zero();
  c.particles.push_back(top);
  c.gravity = Vec3(0, 0, -9.81);
  Simulation s(c);
  s.step(40000);
  const Stats st = s.stats();
  ASSERT_EQ(st.contacts, 2u);
  ASSERT_EQ(st.wall_contacts, 1u);
  double mgz = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) mgz += s.mass(i) * 9.81 * (s.position(i).z() - c.box.lo.z());
  EXPECT_NEAR(st.pressure_tensor[2] * st.volume, mgz, 1e-6 * mgz);
  EXPECT_NEAR(st.virial_pairs[2] + st.virial_walls[2], mgz, 1e-6 * mgz);
  EXPECT_GT(st.virial_walls[2], 0.2 * mgz);  // the floor's share is not small
}

namespace {
// N spheres far apart (no contact within the run) with random velocities and a drift.
Config ideal_gas(const Vec3& drift) {
  Config c;
  const int n = 10;
  const double a = 4.0 * kR;
  c.box.lo = Vec3::Zero();
  c.box.hi = Vec3(n * a, n * a, n * a);
  c.box.periodic = {true, true, true};
  c.gravity = Vec3::Zero();
  c.model = {NormalKind::Walton, TangentialKind::None, CohesionKind::None};
  GroupConfig g;
  g.radius = kR;
  g.density = 2500.0;
  g.contact.k1 = 200.0;
  g.contact.e = 0.9;
  c.groups = {g};
  core::Rng rng(7);
  for (const Vec3& x : simple_cubic_lattice(Vec3::Zero(), a, n, n, n)) {
    ParticleInit p;
    p.x = x;
    p.v = drift + Vec3(rng.normal(0.0, 1e-3), rng.normal(0.0, 1e-3), rng.normal(0.0, 1e-3));
    c.particles.push_back(p);
  }
  return c;
}
}  // namespace

TEST(DemPressure, AnIdealGasHasTheKineticPressureAboutItsMeanVelocity) {
  Simulation s(ideal_gas(Vec3::Zero())), drifting(ideal_gas(Vec3(0.01, -0.02, 0.005)));
  s.step(100);
  drifting.step(100);
  const Stats st = s.stats(), sd = drifting.stats();
  ASSERT_EQ(st.contacts, 0u);
  const auto k = kinetic_tensor(s);
  for (int a = 0; a < 6; ++a) {
    EXPECT_EQ(st.virial_pairs[a], 0.0);
    EXPECT_EQ(st.virial_walls[a], 0.0);
    EXPECT_NEAR(st.pressure_tensor[a], k[a] / st.volume, 1e-13 * std::abs(k[0] / st.volume)) << a;
    // A uniform drift does not change the pressure.
    EXPECT_NEAR(sd.pressure_tensor[a], st.pressure_tensor[a], 1e-9 * st.pressure) << a;
  }
  // P = N kT / V with kT = Σ m |v − V|² / (3N) = 2 E_kin / (3N) about the mean velocity.
  double m = 0.0, e2 = 0.0;
  Vec3 mom = Vec3::Zero();
  for (std::size_t i = 0; i < s.size(); ++i) {
    m += s.mass(i);
    mom += s.mass(i) * s.velocity(i);
    e2 += s.mass(i) * s.velocity(i).squaredNorm();
  }
  const double kT = (e2 - mom.squaredNorm() / m) / (3.0 * double(s.size()));
  EXPECT_NEAR(st.pressure, double(s.size()) * kT / st.volume, 1e-9 * st.pressure);
  // Isotropic within statistics (1000 spheres: each diagonal ±4.5 %), off-diagonals ≈ 0.
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(st.pressure_tensor[a] / st.pressure, 1.0, 0.15) << a;
  for (int a = 3; a < 6; ++a) EXPECT_NEAR(st.pressure_tensor[a] / st.pressure, 0.0, 0.15) << a;
}

namespace {
// A dense frictional box with walls on the sides and bottom, periodic in y, gravity.
Config dense_box() {
  Config c;
  const int nx = 10, ny = 10, nz = 8;
  const double a = 1.02 * 2.0 * kR;
  c.box.lo = Vec3::Zero();
  c.box.hi = Vec3(nx * a, ny * a, 1.25 * nz * a);
  c.box.periodic = {false, true, false};
  c.model = {NormalKind::Walton, TangentialKind::Walton, CohesionKind::None};
  GroupConfig g;
  g.radius = kR;
  g.density = 2500.0;
  g.contact.k1 = 200.0;
  g.contact.e = 0.8;
  g.contact.kt = 2.0 / 7.0 * 200.0;
  g.contact.mu = 0.4;
  c.groups = {g};
  c.skin = 0.4 * kR;
  core::Rng rng(3);
  for (const Vec3& x : simple_cubic_lattice(Vec3::Zero(), a, nx, ny, nz)) {
    ParticleInit p;
    p.x = x;
    p.v = Vec3(rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1));
    c.particles.push_back(p);
  }
  return c;
}
}  // namespace

#ifdef _OPENMP
TEST(DemPressure, OneTwoAndThreeThreadsGiveTheSameBits) {
  const Config c = dense_box();
  const int saved = omp_get_max_threads();
  std::vector<Stats> out;
  for (int t : {1, 2, 3}) {
    omp_set_num_threads(t);
    Simulation s(c);
    s.step(700);
    out.push_back(s.stats());
  }
  omp_set_num_threads(saved);
  ASSERT_GT(out[0].contacts, 50u);
  ASSERT_GT(out[0].wall_contacts, 10u);
  for (std::size_t r = 1; r < out.size(); ++r)
    for (int a = 0; a < 6; ++a) {
      EXPECT_EQ(out[r].virial_pairs[a], out[0].virial_pairs[a]) << "threads " << r + 1 << ", component " << a;
      EXPECT_EQ(out[r].virial_walls[a], out[0].virial_walls[a]) << "threads " << r + 1 << ", component " << a;
      EXPECT_EQ(out[r].pressure_tensor[a], out[0].pressure_tensor[a]) << "threads " << r + 1 << ", component " << a;
    }
}
#endif

TEST(DemPressure, SurvivesACheckpointAndDoesNotPerturbTheRun) {
  const Config c = dense_box();
  Simulation ref(c);
  ref.step(300);
  ref.step(300);
  Simulation s(c);
  s.step(300);
  const Stats before = s.stats();
  io::ArchiveWriter w;
  s.save_state(w);
  Simulation r(c);
  io::ArchiveReader in(w.bytes(), "state");
  r.load_state(in);
  const Stats after = r.stats();
  for (int a = 0; a < 6; ++a) EXPECT_EQ(after.pressure_tensor[a], before.pressure_tensor[a]) << a;
  r.step(300);
  // Measured at the end of each batch only: the trajectory is that of one batch of 600.
  Simulation one(c);
  one.step(600);
  EXPECT_EQ(one.particles().x, ref.particles().x);
  EXPECT_EQ(r.particles().x, ref.particles().x);
  for (int a = 0; a < 6; ++a) EXPECT_EQ(r.stats().pressure_tensor[a], ref.stats().pressure_tensor[a]) << a;
  EXPECT_GT(before.virial_walls[2], 0.0);
}

namespace {
// tests/data/dem/lammps_pressure/packing.data (atom_style sphere: id type diameter density
// x y z; Velocities: id vx vy vz ωx ωy ωz), read into a frictionless Hooke configuration
// with the LAMMPS input's coefficients.
Config lammps_packing() {
  std::ifstream in(std::string(GRAINFLOW_TEST_DATA) + "/dem/lammps_pressure/packing.data");
  Config c;
  c.box.periodic = {true, true, true};
  c.gravity = Vec3::Zero();
  c.model = {NormalKind::Hooke, TangentialKind::None, CohesionKind::None};
  GroupConfig g;
  g.radius = 0.5e-3;
  g.density = 2500.0;
  g.contact.k1 = 100.0;
  g.contact.gamma_n = 828.628;
  c.groups = {g};
  c.dt = 5e-6;
  std::string line, section;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    double lo = 0, hi = 0;
    std::string a, b;
    if (line.find("lo ") != std::string::npos && (s >> lo >> hi >> a >> b)) {
      const int axis = a[0] - 'x';
      c.box.lo[axis] = lo;
      c.box.hi[axis] = hi;
      continue;
    }
    if (line.rfind("Atoms", 0) == 0 || line.rfind("Velocities", 0) == 0) {
      section = line.substr(0, 5);
      continue;
    }
    std::size_t id = 0;
    if (!(s >> id) || id == 0) continue;
    if (c.particles.size() < id) c.particles.resize(id);
    ParticleInit& p = c.particles[id - 1];
    if (section == "Atoms") {
      int type = 0;
      double diameter = 0, density = 0;
      s >> type >> diameter >> density >> p.x.x() >> p.x.y() >> p.x.z();
      p.radius = 0.5 * diameter;
    } else if (section == "Veloc") {
      s >> p.v.x() >> p.v.y() >> p.v.z() >> p.omega.x() >> p.omega.y() >> p.omega.z();
    }
  }
  return c;
}
}  // namespace

TEST(DemPressure, DensePeriodicPackingMatchesLammpsComputePressure) {
  // LAMMPS's compute pressure of the same run (in.pressure, README.md there): 216 spheres
  // in a periodic cube, frictionless gran/hooke/history, every contact across the cube's
  // faces included; the pressure tensor every 100 steps at %.17g.
  const Config c = lammps_packing();
  ASSERT_EQ(c.particles.size(), 216u);
  std::ifstream ref(std::string(GRAINFLOW_TEST_DATA) + "/dem/lammps_pressure/pressure_ref.txt");
  std::string line;
  Simulation s(c);
  int rows = 0;
  double worst = 0.0;
  while (std::getline(ref, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream in(line);
    std::uint64_t step = 0;
    std::array<double, 6> p{};
    in >> step;
    for (double& x : p) in >> x;
    ASSERT_TRUE(in) << line;
    if (step > s.steps()) s.step(step - s.steps());
    const Stats st = s.stats();
    if (step > 0) {
      EXPECT_GT(st.contacts, 50u) << "step " << step;
    }
    const double scale = std::abs(p[0] + p[1] + p[2]) / 3.0;
    for (int a = 0; a < 6; ++a) {
      EXPECT_NEAR(st.pressure_tensor[a], p[a], 1e-10 * scale) << "step " << step << ", component " << a;
      worst = std::max(worst, std::abs(st.pressure_tensor[a] - p[a]) / scale);
    }
    ++rows;
  }
  EXPECT_EQ(rows, 5);
  std::printf("largest |P_ab − LAMMPS| / P over 5 rows: %.2e\n", worst);
}
