// Extended-XYZ writer: frames written and read back by XyzReader are identical (shortest
// round-trip number formatting), and the output is only visible under its name after close().
#include "engine/io/xyz_writer.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "engine/core/error.hpp"
#include "engine/io/lammps_dump_reader.hpp"
#include "engine/core/rng.hpp"
#include "engine/io/xyz_reader.hpp"

using namespace grainflow;
using namespace grainflow::core;
using namespace grainflow::io;

namespace {

ParticleFrame random_frame(Rng& rng, int n, bool velocity) {
  ParticleFrame f;
  f.dim = 3;
  f.time = rng.uniform(0, 100);
  f.timestep = 12345;
  f.has_box = true;
  f.box_lo = Vec3(-1.5, 0.0, 2.0);
  f.box_hi = Vec3(8.5, 10.0, 7.25);
  f.periodic = {true, false, true};
  f.type_names = {"small", "large"};
  std::vector<double> charge;
  for (int i = 0; i < n; ++i) {
    f.id.push_back(1000 + 7 * i);
    f.position.emplace_back(rng.uniform(-1.5, 8.5), rng.uniform(0, 10), rng.uniform(2, 7.25));
    f.radius.push_back(rng.uniform(0.1, 0.6) / 3.0);
    f.type.push_back(1 + static_cast<int>(rng.below(2)));
    if (velocity) f.velocity.emplace_back(rng.normal(), rng.normal(), 1e-12 * rng.normal());
    charge.push_back(rng.normal() * 1e5);
  }
  f.extra.emplace_back("charge", charge);
  f.extra.emplace_back("c_stress[1]", std::vector<double>(n, -0.1));
  return f;
}

void expect_same(const ParticleFrame& a, const ParticleFrame& b) {
  EXPECT_EQ(a.dim, b.dim);
  EXPECT_EQ(a.time, b.time);
  EXPECT_EQ(a.timestep, b.timestep);
  EXPECT_EQ(a.has_box, b.has_box);
  EXPECT_EQ(a.box_lo, b.box_lo);
  EXPECT_EQ(a.box_hi, b.box_hi);
  EXPECT_EQ(a.triclinic, b.triclinic);
  EXPECT_EQ(a.tilt, b.tilt);
  EXPECT_EQ(a.periodic, b.periodic);
  EXPECT_EQ(a.id, b.id);
  EXPECT_EQ(a.position, b.position);
  EXPECT_EQ(a.radius, b.radius);
  EXPECT_EQ(a.velocity, b.velocity);
  EXPECT_EQ(a.type, b.type);
  EXPECT_EQ(a.type_names, b.type_names);
  ASSERT_EQ(a.extra.size(), b.extra.size());
  for (std::size_t k = 0; k < a.extra.size(); ++k) EXPECT_EQ(a.extra[k].second, b.extra[k].second) << a.extra[k].first;
}

}  // namespace

TEST(XyzWriter, RoundTripIsExact) {
  Rng rng(5);
  std::vector<ParticleFrame> frames = {random_frame(rng, 50, true), random_frame(rng, 30, false)};
  // The reader numbers named species by first appearance: make that the frame's order.
  frames[0].type[0] = 1;
  frames[0].type[1] = 2;
  const std::string path = std::string(GRAINFLOW_TEST_OUT) + "/roundtrip.xyz";
  std::filesystem::create_directories(GRAINFLOW_TEST_OUT);
  std::filesystem::remove(path);
  {
    XyzWriter w(path);
    for (const auto& f : frames) w.write(f);
    EXPECT_FALSE(std::filesystem::exists(path)) << "visible before close()";
    w.close();
  }
  ASSERT_TRUE(std::filesystem::exists(path));
  XyzReader r(path);
  ParticleFrame g;
  for (auto& f : frames) {
    ASSERT_TRUE(r.next(g));
    expect_same(f, g);
    EXPECT_EQ(g.extra[0].first, "charge");
    EXPECT_EQ(g.extra[1].first, "c_stress[1]");
  }
  EXPECT_FALSE(r.next(g));
}

TEST(XyzWriter, HeaderCarriesRadiusLatticeTime) {
  ParticleFrame f;
  f.dim = 2;
  f.time = 0.25;
  f.has_box = true;
  f.box_lo = Vec3(0, 0, 0);
  f.box_hi = Vec3(4, 2, 0);
  f.periodic = {true, true, false};
  f.id = {1};
  f.position = {Vec3(1, 1, 0)};
  f.radius = {0.5};
  f.type = {1};
  f.velocity = {Vec3(0.1, 0, 0)};
  f.extra.push_back({"bad name:x", {3.0}});
  std::ostringstream os;
  write_xyz_frame(os, f);
  EXPECT_EQ(os.str(),
            "1\n"
            "Lattice=\"4 0 0 0 2 0 0 0 1\" Origin=\"0 0 -0.5\" pbc=\"T T F\" "
            "Properties=id:I:1:type:I:1:pos:R:3:radius:R:1:velo:R:3:bad_name_x:R:1 Time=0.25\n"
            "1 1 1 1 0 0.5 0.1 0 0 3\n");
}

// Spins as OVITO and ASE take them: omegax omegay omegaz (or omega_x …, what the reader
// makes of omega:R:3) become one omega:R:3; a lone "omegaz" stays a scalar.
TEST(XyzWriter, VectorColumnsAreOneProperty) {
  ParticleFrame f;
  f.id = {7, 9};
  f.type = {1, 2};
  f.position = {Vec3(1, 2, 3), Vec3(4, 5, 6)};
  f.radius = {0.5, 0.25};
  f.extra = {{"omegax", {1, 2}}, {"omegay", {3, 4}}, {"omegaz", {5, 6}}, {"mass", {1, 1}},
             {"f_x", {0, 0}}, {"f_y", {0, 0}}, {"f_z", {-1, -2}}, {"cz", {8, 9}}};
  std::ostringstream os;
  write_xyz_frame(os, f);
  EXPECT_EQ(os.str(),
            "2\n"
            "Properties=id:I:1:type:I:1:pos:R:3:radius:R:1:omega:R:3:mass:R:1:f:R:3:cz:R:1\n"
            "7 1 1 2 3 0.5 1 3 5 1 0 0 -1 8\n"
            "9 2 4 5 6 0.25 2 4 6 1 0 0 -2 9\n");
  // Read back: the vector's components under the reader's names, the values unchanged.
  const std::string path = std::string(GRAINFLOW_TEST_OUT) + "/vectors.xyz";
  std::filesystem::create_directories(GRAINFLOW_TEST_OUT);
  std::ofstream(path) << os.str();
  XyzReader r(path);
  ParticleFrame g;
  ASSERT_TRUE(r.next(g));
  EXPECT_EQ(g.id, f.id);
  EXPECT_EQ(g.type, f.type);
  ASSERT_NE(g.column("omega_z"), nullptr);
  EXPECT_EQ(*g.column("omega_z"), (std::vector<double>{5, 6}));
  std::ostringstream again;
  write_xyz_frame(again, g);
  EXPECT_EQ(again.str(), os.str()) << "written, read, written: the same text";
}

TEST(XyzWriter, Float32ShortensTheRealsOnly) {
  ParticleFrame f;
  f.has_box = true;
  f.box_hi = Vec3(0.1, 0.2, 0.3);
  f.time = 0.1;
  f.id = {123456789};
  f.type = {3};
  f.position = {Vec3(0.1, 1.0 / 3.0, 2.0)};
  f.radius = {0.05};
  f.velocity = {Vec3(1e-20, -7.25, 0)};
  std::ostringstream os;
  write_xyz_frame(os, f, Precision::float32);
  EXPECT_EQ(os.str(),
            "1\n"
            "Lattice=\"0.1 0 0 0 0.2 0 0 0 0.3\" Origin=\"0 0 0\" pbc=\"F F F\" "
            "Properties=id:I:1:type:I:1:pos:R:3:radius:R:1:velo:R:3 Time=0.1\n"
            "123456789 3 0.1 0.33333334 2 0.05 1e-20 -7.25 0\n");
  // Each real, parsed as a float, is the float nearest the double written.
  const std::string path = std::string(GRAINFLOW_TEST_OUT) + "/float32.xyz";
  std::filesystem::create_directories(GRAINFLOW_TEST_OUT);
  std::ofstream(path) << os.str();
  XyzReader r(path);
  ParticleFrame g;
  ASSERT_TRUE(r.next(g));
  EXPECT_EQ(float(g.position[0].y()), float(1.0 / 3.0));
  EXPECT_EQ(float(g.velocity[0].x()), float(1e-20));
  EXPECT_EQ(g.id[0], 123456789);
}

TEST(XyzWriter, TriclinicAndDumpRoundTrip) {
  // LAMMPS triclinic dump -> XYZ -> the same bounding box, tilts and positions.
  LammpsDumpReader in(std::string(GRAINFLOW_TEST_DATA) + "/particles/lammps_triclinic.lammpstrj");
  ParticleFrame f, g;
  ASSERT_TRUE(in.next(f));
  std::filesystem::create_directories(GRAINFLOW_TEST_OUT);
  const std::string path = std::string(GRAINFLOW_TEST_OUT) + "/triclinic.xyz";
  {
    XyzWriter w(path);
    w.write(f);
    w.close();
  }
  XyzReader r(path);
  ASSERT_TRUE(r.next(g));
  EXPECT_TRUE(g.triclinic);
  EXPECT_EQ(g.tilt, f.tilt);
  EXPECT_EQ(g.box_lo, f.box_lo);
  EXPECT_EQ(g.box_hi, f.box_hi);
  EXPECT_EQ(g.position, f.position);
}

TEST(XyzWriter, LeftAsPartialWithoutClose) {
  const std::string path = std::string(GRAINFLOW_TEST_OUT) + "/never_closed.xyz";
  std::filesystem::create_directories(GRAINFLOW_TEST_OUT);
  std::filesystem::remove(path);
  {
    XyzWriter w(path);
    ParticleFrame f;
    f.position = {Vec3::Zero()};
    f.radius = {1};
    f.id = {1};
    f.type = {1};
    w.write(f);
  }
  // Nothing under the final name; the frames written so far stay in the .partial.
  EXPECT_FALSE(std::filesystem::exists(path));
  ASSERT_TRUE(std::filesystem::exists(path + ".partial"));
  XyzReader r(path + ".partial");
  ParticleFrame g;
  EXPECT_TRUE(r.next(g));
  EXPECT_FALSE(r.next(g));
}

TEST(XyzWriter, InconsistentFrameIsAnError) {
  ParticleFrame f;
  f.position = {Vec3::Zero(), Vec3::Ones()};
  f.radius = {1};
  f.id = {1, 2};
  f.type = {1, 1};
  std::ostringstream os;
  EXPECT_THROW(write_xyz_frame(os, f), Error);
}
