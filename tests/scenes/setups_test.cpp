// Set-ups in (issue 15): scenes that say what a LAMMPS user writes, read back from the
// run's own particles.xyz through the one column mapping (initial_file.hpp).
//   LammpsScene.*   the two-sphere oblique collision with spin of
//                   tests/data/dem/lammps_oblique_spin (README.md there) against LAMMPS
//   InitialFile.*   unknown columns are errors; spins, types, masses reach both engines
//   DemSetup.*      per-group coefficients and their mixing rule, K2, Walton's γ, origin
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <sys/wait.h>

#include "engine/dem/simulation.hpp"
#include "engine/io/particle_reader.hpp"
#include "scenes/src/engines/initial_file.hpp"
#include "tests/scenes/cli_support.hpp"

namespace fs = std::filesystem;
using namespace grainflow;

namespace {



const fs::path kLammpsDir = fs::path(GRAINFLOW_TEST_DATA) / "dem" / "lammps_oblique_spin";

// Every frame of a particle file, through the initial-state column mapping.
std::vector<scenes::initial_file::InitialParticles> frames_of(const fs::path& file,
                                                              const std::vector<std::string>& ignore = {}) {
  std::vector<scenes::initial_file::InitialParticles> out;
  auto reader = io::open_particle_file(file.string());
  core::ParticleFrame f;
  while (reader->next(f)) out.push_back(scenes::initial_file::map_columns(f, file.string(), ignore, 3));
  return out;
}

// |a − b| / |b| of two vectors (b ≠ 0).
double rel(const Vec3& a, const Vec3& b) { return (a - b).norm() / b.norm(); }

// Runs the LAMMPS scene with extra --set overrides; the frames of its particles.xyz.
std::vector<scenes::initial_file::InitialParticles> run_lammps_scene(const std::string& name,
                                                                     const std::string& sets = "") {
  const fs::path out = fresh_dir(name);
  const Result r = run("run " + (kLammpsDir / "scene.toml").string() + " -o " + out.string() + sets);
  EXPECT_EQ(r.status, 0) << r.output;
  if (r.status != 0) return {};
  return frames_of(out / "particles.xyz", {"mass"});
}

void write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

}  // namespace

TEST(LammpsScene, ObliqueCollisionWithSpinMatchesGranHookeHistory) {
  // The scene is the LAMMPS input's numbers (no shifted coordinates: system.origin is the
  // region's lower corner); the reference is LAMMPS's own dump of the same run, every 100
  // steps at %.17g. Acceptance: final v and ω within 1e-9 relative, from particles.xyz.
  const auto ours = run_lammps_scene("lammps_oblique");
  const auto ref = frames_of(kLammpsDir / "oblique_spin.dump");
  ASSERT_EQ(ref.size(), 5u);
  ASSERT_EQ(ours.size(), ref.size());
  double worst_v = 0, worst_w = 0, worst_x = 0;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    const auto& a = ours[k];
    const auto& b = ref[k];
    // A fixed dt is honoured exactly: frame k is step 100 k, at time step × dt.
    ASSERT_EQ(a.frame.timestep, b.frame.timestep) << k;
    EXPECT_EQ(a.frame.time, double(b.frame.timestep) * 5.0e-6) << k;
    ASSERT_EQ(a.size(), 2u);
    ASSERT_EQ(a.omega.size(), 2u);
    ASSERT_EQ(b.omega.size(), 2u);
    for (std::size_t i = 0; i < 2; ++i) {
      EXPECT_EQ(a.type[i], b.type[i]);
      EXPECT_EQ(a.radius[i], b.radius[i]);
      worst_x = std::max(worst_x, (a.position[i] - b.position[i]).norm());
      worst_v = std::max(worst_v, rel(a.velocity[i], b.velocity[i]));
      worst_w = std::max(worst_w, rel(a.omega[i], b.omega[i]));
    }
  }
  const auto& a = ours.back();
  const auto& b = ref.back();
  for (std::size_t i = 0; i < 2; ++i) {
    std::printf("final particle %zu: |Δv|/|v| = %.3g, |Δω|/|ω| = %.3g\n", i + 1, rel(a.velocity[i], b.velocity[i]),
                rel(a.omega[i], b.omega[i]));
    EXPECT_LT(rel(a.velocity[i], b.velocity[i]), 1e-9);
    EXPECT_LT(rel(a.omega[i], b.omega[i]), 1e-9);
  }
  std::printf("all frames: max |Δx| %.3g m, |Δv|/|v| %.3g, |Δω|/|ω| %.3g\n", worst_x, worst_v, worst_w);
  EXPECT_LT(worst_v, 1e-9);
  EXPECT_LT(worst_w, 1e-9);
  EXPECT_LT(worst_x, 1e-15);
  // The collision happened: it turned particle 1's spin from (0, 0, 800) rad/s.
  EXPECT_GT(rel(b.omega[0], ref.front().omega[0]), 0.1);
}

TEST(LammpsScene, EveryCoefficientOfTheInputMatters) {
  // The comparison above would not notice a key that is read but not used: changing any
  // of them moves the result far beyond the tolerance.
  const auto ref = frames_of(kLammpsDir / "oblique_spin.dump");
  ASSERT_FALSE(ref.empty());
  for (const std::string set : {"system.contact.gamma_t=414.314", "system.contact.dampflag=false",
                                "system.contact.gamma_n=600.0", "system.contact.kt=20.0"}) {
    const auto ours = run_lammps_scene("lammps_changed", " --set " + set);
    ASSERT_EQ(ours.size(), ref.size()) << set;
    EXPECT_GT(rel(ours.back().velocity[0], ref.back().velocity[0]), 1e-6) << set;
  }
  // Spins from the file: without them (listed in ignore) the collision differs.
  const auto spinless = run_lammps_scene(
      "lammps_spinless", " --set 'system.initial.ignore=[\"omegax\", \"omegay\", \"omegaz\"]'");
  ASSERT_EQ(spinless.size(), ref.size());
  EXPECT_GT(rel(spinless.back().omega[1], ref.back().omega[1]), 1e-3);
}

TEST(DemSetup, PerGroupCoefficientsMixByTheArithmeticMean) {
  // Group 1 (LAMMPS type 2) with its own kn: between the groups the contact takes the mean
  // (100 + 300)/2 = 200 N/m, and γn given for both stays given. The engine, configured with
  // that mixed contact by hand, gives the same bits.
  const auto ours = run_lammps_scene("per_group", " --set 'system.group[1].kn=300.0'");
  ASSERT_EQ(ours.size(), 5u);
  const auto ref = frames_of(kLammpsDir / "oblique_spin.dump");
  dem::Config c;
  c.box.lo = Vec3(-0.005, -0.005, -0.005);
  c.box.hi = c.box.lo + Vec3(0.01, 0.01, 0.01);
  c.gravity = Vec3::Zero();
  c.model = {dem::NormalKind::Hooke, dem::TangentialKind::History, dem::CohesionKind::None};
  dem::GroupConfig g;
  g.density = 2500.0;
  g.contact.k1 = 100.0;
  g.contact.kt = 28.571428571428573;
  g.contact.gamma_n = 828.628;
  g.contact.gamma_t = 300.0;
  g.contact.mu = 0.5;
  g.contact.e = 0.9;
  g.radius = 0.0005;
  dem::GroupConfig g2 = g;
  g2.radius = 0.0006;
  g2.contact.k1 = 300.0;
  c.groups = {g, g2};
  dem::ContactParams mixed = g.contact;
  mixed.k1 = 200.0;
  c.mixed_contact = mixed;
  c.dt = 5e-6;
  c.skin = 2e-4;
  for (std::size_t i = 0; i < 2; ++i) {
    dem::ParticleInit p;
    p.x = ref[0].position[i];
    p.v = ref[0].velocity[i];
    p.omega = ref[0].omega[i];
    p.group = int(i);
    c.particles.push_back(p);
  }
  dem::Simulation s(c);
  s.step(400);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(ours.back().velocity[i], s.velocity(i)) << i;
    EXPECT_EQ(ours.back().omega[i], s.angular_velocity(i)) << i;
  }
  EXPECT_GT(rel(ours.back().velocity[0], ref.back().velocity[0]), 1e-3);  // and it is another collision
}

TEST(DemSetup, WaltonK2AndTangentialExponentReachTheEngine) {
  // Walton's spring with K2 given (e = sqrt(K1/K2) = 0.8; system.contact.e is not used)
  // and γ = 1 in Eq. 2.10, through the scene, against the engine configured directly.
  const std::string sets =
      " --set system.contact.normal=\"walton\" --set system.contact.tangential=\"walton\""
      " --set system.contact.k2=156.25 --set system.contact.e=0.3 --set system.contact.walton_gamma=1.0";
  const auto ours = run_lammps_scene("walton_k2", sets);
  ASSERT_EQ(ours.size(), 5u);
  const auto ref = frames_of(kLammpsDir / "oblique_spin.dump");
  for (const double gamma : {1.0, 1.0 / 3.0}) {
    dem::Config c;
    c.box.lo = Vec3(-0.005, -0.005, -0.005);
    c.box.hi = c.box.lo + Vec3(0.01, 0.01, 0.01);
    c.gravity = Vec3::Zero();
    c.model = {dem::NormalKind::Walton, dem::TangentialKind::Walton, dem::CohesionKind::None};
    dem::GroupConfig g;
    g.density = 2500.0;
    g.contact.k1 = 100.0;
    g.contact.k2 = 156.25;
    g.contact.e = 0.3;
    g.contact.kt = 28.571428571428573;
    g.contact.mu = 0.5;
    g.contact.walton_gamma = gamma;
    g.radius = 0.0005;
    dem::GroupConfig g2 = g;
    g2.radius = 0.0006;
    c.groups = {g, g2};
    c.dt = 5e-6;
    c.skin = 2e-4;
    for (std::size_t i = 0; i < 2; ++i) {
      dem::ParticleInit p;
      p.x = ref[0].position[i];
      p.v = ref[0].velocity[i];
      p.omega = ref[0].omega[i];
      p.group = int(i);
      c.particles.push_back(p);
    }
    dem::Simulation s(c);
    s.step(400);
    const bool same = ours.back().velocity[0] == s.velocity(0) && ours.back().omega[1] == s.angular_velocity(1);
    EXPECT_EQ(same, gamma == 1.0) << "walton_gamma " << gamma;
  }
}

TEST(DemSetup, GivenK2SetsTheRestitution) {
  // A head-on Walton collision with K2 = K1/0.64: e = sqrt(K1/K2) = 0.8 (Eq. 2.9), whatever
  // system.contact.e says.
  const fs::path dir = fresh_dir("k2_head_on");
  write(dir / "pair2.xyz", "2\nProperties=species:S:1:pos:R:3:velo:R:3\n1 -0.0006 0 0 0.1 0 0\n2 0.0006 0 0 -0.1 0 0\n");
  const Result r2 = run("run " + (kLammpsDir / "scene.toml").string() + " -o " + (dir / "out2").string() +
                        " --set system.initial.file=\"" + (dir / "pair2.xyz").string() + "\"" +
                        " --set 'system.group[1].radius=0.0005'" +
                        " --set system.contact.normal=\"walton\" --set system.contact.tangential=\"none\"" +
                        " --set system.contact.k2=156.25 --set system.contact.e=0.3");
  ASSERT_EQ(r2.status, 0) << r2.output;
  const auto f = frames_of(dir / "out2" / "particles.xyz", {"mass"});
  ASSERT_FALSE(f.empty());
  const double v_after = f.back().velocity[1].x() - f.back().velocity[0].x();
  EXPECT_NEAR(v_after / 0.2, 0.8, 2e-3);
}

TEST(InitialFile, UnknownColumnsAreErrorsUntilIgnored) {
  const fs::path dir = fresh_dir("unknown_column");
  write(dir / "pair.xyz",
        "2\nProperties=species:S:1:pos:R:3:velo:R:3:charge:R:1\n1 -0.0006 0 0 0.1 0 0 3.5\n2 0.0006 0 0 -0.1 0 0 "
        "1.0\n");
  const std::string base = "run " + (kLammpsDir / "scene.toml").string() + " --set system.initial.file=\"" +
                           (dir / "pair.xyz").string() + "\"";
  const Result bad = run(base + " -o " + (dir / "bad").string());
  EXPECT_NE(bad.status, 0);
  EXPECT_TRUE(contains(bad.output, "\"charge\"")) << bad.output;
  EXPECT_TRUE(contains(bad.output, "system.initial.ignore")) << bad.output;
  EXPECT_FALSE(fs::exists(dir / "bad" / "particles.xyz"));
  const Result ok = run(base + " -o " + (dir / "ok").string() + " --set 'system.initial.ignore=[\"charge\"]'");
  EXPECT_EQ(ok.status, 0) << ok.output;
  // An ignore entry the file does not have is a typo, not silence.
  const Result typo =
      run(base + " -o " + (dir / "typo").string() + " --set 'system.initial.ignore=[\"charge\", \"chrage\"]'");
  EXPECT_NE(typo.status, 0);
  EXPECT_TRUE(contains(typo.output, "\"chrage\"")) << typo.output;
  // A mass that the radius and density do not give is refused, naming both.
  write(dir / "heavy.xyz",
        "2\nProperties=species:S:1:pos:R:3:mass:R:1\n1 -0.0006 0 0 1.0\n2 0.0006 0 0 1.0\n");
  const Result heavy = run("run " + (kLammpsDir / "scene.toml").string() + " -o " + (dir / "heavy").string() +
                           " --set system.initial.file=\"" + (dir / "heavy.xyz").string() + "\"");
  EXPECT_NE(heavy.status, 0);
  EXPECT_TRUE(contains(heavy.output, "density")) << heavy.output;
}

TEST(InitialFile, EdDisksTakeSpinsFromTheFile) {
  // The ED engine through the same mapping: a LAMMPS-style dump with omegaz.
  const fs::path dir = fresh_dir("ed_spins");
  write(dir / "disks.dump",
        "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n3\nITEM: BOX BOUNDS pp pp pp\n0 24\n0 24\n-0.5 0.5\n"
        "ITEM: ATOMS id type x y z vx vy vz omegaz\n"
        "1 1 4 4 0 0.5 0.1 0 0.25\n2 1 12 12 0 0 0.1 0 -0.5\n3 1 20 6 0 -0.1 0 0 0.75\n");
  const std::string scene =
      "[run]\nengine = \"ed\"\nuntil = 0.5\nseed = 1\n[system]\nbox = [24.0, 24.0]\nmu = 0.3\n"
      "[system.initial]\nkind = \"file\"\nfile = \"disks.dump\"\n[boundary]\nperiodic = [true, true]\n"
      "[output]\npng = false\nmp4 = false\nparticles = true\n";
  write(dir / "scene.toml", scene);
  const Result r = run("run " + (dir / "scene.toml").string() + " -o " + (dir / "out").string());
  ASSERT_EQ(r.status, 0) << r.output;
  auto reader = io::open_particle_file((dir / "out" / "particles.xyz").string());
  core::ParticleFrame f;
  ASSERT_TRUE(reader->next(f));
  const auto first = scenes::initial_file::map_columns(f, "particles.xyz", {}, 2);
  ASSERT_EQ(first.omega.size(), 3u);
  EXPECT_EQ(first.omega[0].z(), 0.25);
  EXPECT_EQ(first.omega[1].z(), -0.5);
  EXPECT_EQ(first.omega[2].z(), 0.75);
  // Two kinds of disk are refused: the ED engine has one.
  write(dir / "two.dump",
        "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp pp pp\n0 24\n0 24\n-0.5 0.5\n"
        "ITEM: ATOMS id type x y z\n1 1 4 4 0\n2 2 12 12 0\n");
  const Result two = run("run " + (dir / "scene.toml").string() + " -o " + (dir / "two").string() +
                         " --set system.initial.file=\"two.dump\"");
  EXPECT_NE(two.status, 0);
  EXPECT_TRUE(contains(two.output, "one kind of disk")) << two.output;
  // A 3D spin component in a 2D run is refused.
  write(dir / "tilt.dump",
        "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp pp pp\n0 24\n0 24\n-0.5 0.5\n"
        "ITEM: ATOMS id type x y z omegax omegay omegaz\n1 1 4 4 0 1 0 0\n");
  const Result tilt = run("run " + (dir / "scene.toml").string() + " -o " + (dir / "tilt").string() +
                          " --set system.initial.file=\"tilt.dump\"");
  EXPECT_NE(tilt.status, 0);
  EXPECT_TRUE(contains(tilt.output, "omegax")) << tilt.output;
}

TEST(InitialFile, LammpsDataFileGivesTheSameRunAsTheDump) {
  // in.oblique_spin's write_data at step 0 (atom_style sphere: Atoms and Velocities with
  // spins): the scene started from it reproduces the run started from the dump's step 0.
  const auto from_dump = run_lammps_scene("from_dump");
  const auto from_data = run_lammps_scene("from_data", " --set system.initial.file=\"oblique_spin.data\"");
  ASSERT_EQ(from_data.size(), 5u);
  ASSERT_EQ(from_dump.size(), 5u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(from_data.back().position[i], from_dump.back().position[i]);
    EXPECT_EQ(from_data.back().velocity[i], from_dump.back().velocity[i]);
    EXPECT_EQ(from_data.back().omega[i], from_dump.back().omega[i]);
  }
  // A density the group does not have, and a section an initial state does not take, are
  // errors naming them.
  const fs::path dir = fresh_dir("data_errors");
  std::ifstream in(kLammpsDir / "oblique_spin.data");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string base = "run " + (kLammpsDir / "scene.toml").string();
  const Result dense = run(base + " -o " + (dir / "dense").string() + " --set system.initial.file=\"" +
                           (kLammpsDir / "oblique_spin.data").string() + "\" --set 'system.group[1].density=3000.0'");
  EXPECT_NE(dense.status, 0);
  EXPECT_TRUE(contains(dense.output, "density")) << dense.output;
  std::string masses = text;
  masses.replace(masses.find("Atoms # sphere"), 0, "Masses\n\n1 1.0\n2 1.0\n\n");
  write(dir / "masses.data", masses);
  const Result m = run(base + " -o " + (dir / "masses").string() + " --set system.initial.file=\"" +
                       (dir / "masses.data").string() + "\"");
  EXPECT_NE(m.status, 0);
  EXPECT_TRUE(contains(m.output, "\"Masses\"")) << m.output;
}
