// LAMMPS text-dump writer: the layout LAMMPS writes (TIME before TIMESTEP, boundary flags,
// the ATOMS columns of the issue), exact round trips through LammpsDumpReader at float64,
// a 2D frame as LAMMPS writes a 2D run, and the file visible only after close().
#include "engine/io/lammps_dump_writer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <sstream>

#include "engine/core/error.hpp"
#include "engine/core/rng.hpp"
#include "engine/io/lammps_dump_reader.hpp"

using namespace grainflow;
using namespace grainflow::core;
using namespace grainflow::io;

namespace {

ParticleFrame sphere_frame(Rng& rng, int n) {
  ParticleFrame f;
  f.time = 0.00123456789;
  f.timestep = 4200;
  f.has_box = true;
  f.box_lo = Vec3(-0.5, 0.0, 0.0);
  f.box_hi = Vec3(0.5, 0.01, 0.02);
  f.periodic = {true, true, false};
  std::vector<double> wx, wy, wz, mass;
  for (int i = 0; i < n; ++i) {
    f.id.push_back(i + 1);
    f.type.push_back(1 + static_cast<int>(rng.below(3)));
    f.position.emplace_back(rng.uniform(-0.5, 0.5), rng.uniform(0, 0.01), rng.uniform(0, 0.02));
    f.radius.push_back(rng.uniform(1e-4, 5e-4));
    f.velocity.emplace_back(rng.normal(), rng.normal(), rng.normal());
    wx.push_back(rng.normal() * 100), wy.push_back(rng.normal()), wz.push_back(-rng.normal());
    mass.push_back(rng.uniform(1e-6, 1e-5));
  }
  f.extra = {{"omegax", wx}, {"omegay", wy}, {"omegaz", wz}, {"mass", mass}};
  return f;
}

}  // namespace

TEST(LammpsDumpWriter, LayoutIsLammpsDumpCustom) {
  ParticleFrame f;
  f.dim = 2;
  f.time = 1.5;
  f.has_box = true;
  f.box_hi = Vec3(4, 2, 0);
  f.periodic = {false, true, false};
  f.id = {17};
  f.type = {2};
  f.position = {Vec3(1, 1, 0)};
  f.radius = {0.5};
  f.velocity = {Vec3(0.1, -0.2, 0)};
  f.extra = {{"omegax", {0}}, {"omegay", {0}}, {"omegaz", {0.3}}, {"mass", {1}}};
  std::ostringstream os;
  // The ED engine's frames have no step: the caller's frame number stands in.
  write_lammps_dump_frame(os, f, 12);
  EXPECT_EQ(os.str(),
            "ITEM: TIME\n1.5\n"
            "ITEM: TIMESTEP\n12\n"
            "ITEM: NUMBER OF ATOMS\n1\n"
            "ITEM: BOX BOUNDS ff pp pp\n0 4\n0 2\n-0.5 0.5\n"
            "ITEM: ATOMS id type radius x y z vx vy vz omegax omegay omegaz mass\n"
            "17 2 0.5 1 1 0 0.1 -0.2 0 0 0 0.3 1\n");
  // A frame's own step wins.
  f.timestep = 99;
  os.str("");
  write_lammps_dump_frame(os, f, 12);
  EXPECT_NE(os.str().find("ITEM: TIMESTEP\n99\n"), std::string::npos) << os.str();
}

TEST(LammpsDumpWriter, RoundTripIsExactAndContinues) {
  Rng rng(8);
  std::vector<ParticleFrame> frames = {sphere_frame(rng, 40), sphere_frame(rng, 25)};
  frames[1].triclinic = true;
  frames[1].tilt = Vec3(0.1, 0.0, -0.002);
  const std::string path = std::string(GRAINFLOW_TEST_OUT) + "/roundtrip.lammpstrj";
  std::filesystem::create_directories(GRAINFLOW_TEST_OUT);
  std::filesystem::remove(path);
  std::uint64_t after_first = 0;
  {
    LammpsDumpWriter w(path);
    w.write(frames[0], 0);
    after_first = w.flush();
    w.write(frames[1], 1);  // cut off below by the resumed writer, then written again
  }
  EXPECT_FALSE(std::filesystem::exists(path)) << "visible before close()";
  {
    LammpsDumpWriter w(path, after_first, 1);
    w.write(frames[1], 1);
    EXPECT_EQ(w.frames(), 2);
    w.close();
  }
  LammpsDumpReader r(path);
  ParticleFrame g;
  for (const auto& f : frames) {
    ASSERT_TRUE(r.next(g));
    EXPECT_EQ(g.time, f.time);
    EXPECT_EQ(g.timestep, f.timestep);
    EXPECT_EQ(g.box_lo, f.box_lo);
    EXPECT_EQ(g.box_hi, f.box_hi);
    EXPECT_EQ(g.triclinic, f.triclinic);
    EXPECT_EQ(g.tilt, f.tilt);
    EXPECT_EQ(g.periodic, f.periodic);
    EXPECT_EQ(g.id, f.id);
    EXPECT_EQ(g.type, f.type);
    EXPECT_EQ(g.position, f.position);
    EXPECT_EQ(g.radius, f.radius);
    EXPECT_EQ(g.velocity, f.velocity);
    for (const char* name : {"omegax", "omegay", "omegaz", "mass"}) {
      ASSERT_NE(g.column(name), nullptr) << name;
      const auto& want = std::find_if(f.extra.begin(), f.extra.end(), [&](const auto& e) { return e.first == name; })->second;
      EXPECT_EQ(*g.column(name), want) << name;
    }
  }
  EXPECT_FALSE(r.next(g));
}

TEST(LammpsDumpWriter, Float32AndFramesWithoutBox) {
  ParticleFrame f;
  f.id = {1, 2};
  f.type = {1, 1};
  f.position = {Vec3(0.1, 0.2, 0.3), Vec3(1.0 / 3.0, 2, 3)};
  f.radius = {0.5, 0.5};
  std::ostringstream os;
  write_lammps_dump_frame(os, f, 0, Precision::float32);
  EXPECT_EQ(os.str(),
            "ITEM: TIMESTEP\n0\n"
            "ITEM: NUMBER OF ATOMS\n2\n"
            "ITEM: BOX BOUNDS ff ff ff\n0.1 0.3333333333333333\n0.2 2\n0.3 3\n"
            "ITEM: ATOMS id type radius x y z\n"
            "1 1 0.5 0.1 0.2 0.3\n"
            "2 1 0.5 0.33333334 2 3\n");
}

TEST(LammpsDumpWriter, InconsistentFrameIsAnError) {
  ParticleFrame f;
  f.position = {Vec3::Zero(), Vec3::Ones()};
  f.radius = {1};
  f.id = {1, 2};
  f.type = {1, 1};
  std::ostringstream os;
  EXPECT_THROW(write_lammps_dump_frame(os, f, 0), Error);
}
