// LAMMPS/LIGGGHTS dump and XYZ readers: every format variant in tests/data/particles, and
// every malformed case must throw grainflow::Error naming file:line.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/lammps_dump_reader.hpp"
#include "engine/io/particle_reader.hpp"
#include "tests/io/reader_test_support.hpp"
#include "engine/io/xyz_reader.hpp"

using namespace grainflow;
using namespace grainflow::core;
using namespace grainflow::io;
using namespace grainflow::io::test;

namespace {




// Reading `text` must throw an Error whose message starts with "path:line:" and contains
// `fragment`.
void expect_error(const std::string& name, const std::string& text, int line, const std::string& fragment) {
  const std::string path = write_temp(name, text);
  try {
    read_all(path);
    ADD_FAILURE() << name << ": no error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    const std::string where = path + ":" + std::to_string(line) + ":";
    EXPECT_EQ(msg.rfind(where, 0), 0u) << name << ": expected prefix " << where << "\n got: " << msg;
    EXPECT_NE(msg.find(fragment), std::string::npos) << name << ": expected '" << fragment << "' in: " << msg;
  }
}

const std::string kDumpHead =
    "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\n";

}  // namespace

TEST(LammpsDump, TwoFramesWithVelocities) {
  auto reader = open_particle_file(data("lammps_two_frames.lammpstrj"));
  EXPECT_EQ(reader->format(), "lammps-dump");
  ParticleFrame f;
  ASSERT_TRUE(reader->next(f));
  EXPECT_EQ(f.timestep, 0);
  EXPECT_EQ(f.time, 0.0);
  ASSERT_EQ(f.size(), 4u);
  EXPECT_EQ(f.dim, 3);
  EXPECT_TRUE(f.has_box);
  EXPECT_EQ(f.box_lo, Vec3(0, 0, -0.5));
  EXPECT_EQ(f.box_hi, Vec3(10, 10, 20));
  EXPECT_TRUE(f.periodic[0] && f.periodic[1] && !f.periodic[2]);
  EXPECT_EQ(f.id[2], 3);
  EXPECT_EQ(f.type[2], 2);
  EXPECT_EQ(f.position[1], Vec3(3.25, 4.75, 1.0));
  ASSERT_TRUE(f.has_velocity());
  EXPECT_EQ(f.velocity[2], Vec3(-0.15, 0.025, 1.0));
  EXPECT_EQ(f.radius[0], LammpsDumpReader::kDefaultRadius);
  EXPECT_TRUE(f.extra.empty());
  ASSERT_TRUE(reader->next(f));
  EXPECT_EQ(f.timestep, 1000);
  EXPECT_DOUBLE_EQ(f.time, 0.005);
  EXPECT_EQ(f.id[0], 2);  // file order is kept; ids say who is who
  EXPECT_EQ(f.velocity[2].z(), -9.9);
  EXPECT_FALSE(reader->next(f));
  EXPECT_FALSE(reader->next(f));
}

TEST(LammpsDump, LiggghtsRadiusAndDuplicateTypeColumn) {
  const auto frames = read_all(data("liggghts_radius.liggghts"));
  ASSERT_EQ(frames.size(), 1u);
  const auto& f = frames[0];
  EXPECT_EQ(f.timestep, 35000);
  EXPECT_TRUE(std::isnan(f.time));
  ASSERT_EQ(f.size(), 3u);
  EXPECT_EQ(f.radius[0], 0.0025);
  EXPECT_EQ(f.radius[2], 0.005);
  EXPECT_EQ(f.id[2], 31);
  EXPECT_EQ(f.type[2], 2);
  EXPECT_FALSE(f.periodic[0] || f.periodic[1] || f.periodic[2]);
  EXPECT_EQ(f.velocity[0], Vec3(0.01, 0.02, -0.3));
  ASSERT_NE(f.column("type_2"), nullptr);
  EXPECT_EQ((*f.column("type_2"))[2], 2.0);
  ASSERT_NE(f.column("omegax"), nullptr);
  EXPECT_EQ((*f.column("omegax"))[1], 0.1);
  ASSERT_NE(f.column("fz"), nullptr);
  EXPECT_EQ((*f.column("fz"))[2], -0.0016);
  EXPECT_EQ((*f.column("ix"))[0], 0.0);
}

TEST(LammpsDump, ScaledCoordinates2D) {
  const auto frames = read_all(data("lammps_scaled_2d.lammpstrj"));
  ASSERT_EQ(frames.size(), 1u);
  const auto& f = frames[0];
  EXPECT_EQ(f.dim, 2);  // z bounds −0.5..0.5, every z = 0
  EXPECT_EQ(f.position[0], Vec3(-2.0, 0.0, 0.0));
  EXPECT_EQ(f.position[1], Vec3(2.0, 1.0, 0.0));
  EXPECT_EQ(f.position[2], Vec3(6.0, 3.0, 0.0));
  EXPECT_FALSE(f.has_velocity());
  EXPECT_EQ(f.column("vx"), nullptr);
}

TEST(LammpsDump, DiameterUnwrappedAndExtraColumns) {
  const auto frames = read_all(data("lammps_diameter.lammpstrj"));
  ASSERT_EQ(frames.size(), 1u);
  const auto& f = frames[0];
  EXPECT_EQ(f.radius[0], 0.05);
  EXPECT_EQ(f.radius[1], 0.1);
  EXPECT_EQ(f.position[0], Vec3(0.25, 0.5, 1.25));  // xu may leave the box
  EXPECT_EQ(f.type[1], 3);
  ASSERT_NE(f.column("mass"), nullptr);
  EXPECT_EQ((*f.column("mass"))[1], 0.00418879);
  EXPECT_TRUE(std::isnan((*f.column("c_ke"))[0]));  // LAMMPS writes nan for undefined computes
  EXPECT_EQ((*f.column("diameter"))[1], 0.2);
}

TEST(LammpsDump, TriclinicScaledUsesTiltedCell) {
  const auto frames = read_all(data("lammps_triclinic.lammpstrj"));
  const auto& f = frames.at(0);
  EXPECT_TRUE(f.triclinic);
  EXPECT_EQ(f.tilt, Vec3(2.0, -1.0, 0.0));
  EXPECT_EQ(f.box_lo, Vec3(-1.0, 0.0, 0.0));  // bounding box as written
  EXPECT_EQ(f.box_hi, Vec3(11.0, 10.0, 10.0));
  // cell: xlo = −1 − min(0, 2, −1, 1) = 0, lx = 9; x = xlo + xs·lx + ys·xy + zs·xz
  EXPECT_EQ(f.position[0], Vec3(0.0, 0.0, 0.0));
  EXPECT_EQ(f.position[1], Vec3(5.0, 5.0, 5.0));
}

TEST(Xyz, ExtendedMultiFrame) {
  auto reader = open_particle_file(data("extended_two_frames.xyz"));
  EXPECT_EQ(reader->format(), "xyz");
  ParticleFrame f;
  ASSERT_TRUE(reader->next(f));
  EXPECT_EQ(f.time, 0.5);
  EXPECT_EQ(f.timestep, 50);
  EXPECT_TRUE(f.has_box);
  EXPECT_EQ(f.box_hi, Vec3(10, 10, 4));
  EXPECT_FALSE(f.triclinic);
  EXPECT_TRUE(f.periodic[0] && f.periodic[1] && !f.periodic[2]);
  ASSERT_EQ(f.size(), 3u);
  EXPECT_EQ(f.type, (std::vector<int>{1, 2, 1}));
  EXPECT_EQ(f.type_names, (std::vector<std::string>{"Cu", "Ag"}));
  EXPECT_EQ(f.radius[1], 0.5);
  EXPECT_EQ(f.velocity[1], Vec3(0.0, 0.2, 0.0));
  EXPECT_EQ(f.id, (std::vector<std::int64_t>{1, 2, 3}));
  EXPECT_EQ((*f.column("mass"))[1], 4.0);
  ASSERT_TRUE(reader->next(f));
  EXPECT_EQ(f.timestep, 100);
  // Species keep their type over the whole file; a new species gets the next type.
  EXPECT_EQ(f.type, (std::vector<int>{2, 1, 3}));
  EXPECT_EQ(f.type_names, (std::vector<std::string>{"Cu", "Ag", "Au"}));
  EXPECT_EQ(f.radius[2], 0.75);
  EXPECT_FALSE(reader->next(f));
}

TEST(Xyz, Ovito2DWithIdTypeDiameterAndLogical) {
  const auto frames = read_all(data("ovito_diameter_2d.xyz"));
  const auto& f = frames.at(0);
  EXPECT_EQ(f.dim, 2);
  EXPECT_EQ(f.time, 12.5);
  EXPECT_EQ(f.box_lo, Vec3(-10, -5, 0));
  EXPECT_EQ(f.box_hi, Vec3(10, 5, 0));
  EXPECT_EQ(f.id, (std::vector<std::int64_t>{7, 8}));
  EXPECT_EQ(f.type, (std::vector<int>{2, 1}));
  EXPECT_EQ(f.position[0], Vec3(-1.5, 2.5, 0.0));
  EXPECT_EQ(f.radius[0], 0.5);
  EXPECT_EQ(f.radius[1], 0.25);
  EXPECT_EQ((*f.column("force_z"))[1], -0.3);
  EXPECT_EQ((*f.column("selected"))[0], 1.0);
  EXPECT_EQ((*f.column("selected"))[1], 0.0);
}

TEST(Xyz, PlainMultiFrameWithDefaultRadius) {
  const auto frames = read_all(data("plain_two_frames.xyz"));
  ASSERT_EQ(frames.size(), 2u);
  const auto& f = frames[1];
  EXPECT_FALSE(f.has_box);
  EXPECT_EQ(f.dim, 2);  // every z is 0
  EXPECT_EQ(f.position[1], Vec3(1.3, 0.0, 0.0));
  EXPECT_EQ(f.radius[0], XyzReader::kDefaultRadius);
  EXPECT_EQ(f.type_names, (std::vector<std::string>{"C", "O"}));
  EXPECT_EQ((*f.column("column5"))[1], 2.6);
  EXPECT_TRUE(std::isnan(f.time));
  EXPECT_EQ(f.timestep, -1);
}

TEST(Xyz, NumericSpeciesAreTypes) {
  const auto path = write_temp("numeric_species.xyz", "2\nLAMMPS dump xyz\n3 0 0 1\n1 1 1 1\n");
  const auto frames = read_all(path);
  EXPECT_EQ(frames.at(0).type, (std::vector<int>{3, 1}));
  EXPECT_TRUE(frames[0].type_names.empty());
  EXPECT_EQ(frames[0].dim, 3);
}

TEST(ParticleFrame, StandardColumns) {
  const auto frames = read_all(data("lammps_two_frames.lammpstrj"));
  const auto& f = frames[0];
  EXPECT_EQ((*f.column("x"))[1], 3.25);
  EXPECT_EQ((*f.column("z"))[3], 5.0);
  EXPECT_EQ((*f.column("vy"))[0], -0.2);
  EXPECT_EQ((*f.column("id"))[3], 4.0);
  EXPECT_EQ((*f.column("type"))[3], 2.0);
  EXPECT_EQ((*f.column("radius"))[0], 0.5);
  EXPECT_NEAR((*f.column("speed"))[0], std::sqrt(0.01 + 0.04 + 0.09), 1e-15);
  EXPECT_EQ(f.column("speed"), f.column("speed"));  // cached, stable pointer
  EXPECT_EQ(f.column("nope"), nullptr);
  const auto names = f.column_names();
  EXPECT_NE(std::find(names.begin(), names.end(), "speed"), names.end());
}

TEST(ParticleFile, SnifferRejectsOtherContent) {
  EXPECT_THROW(open_particle_file(write_temp("empty.txt", "\n\n")), Error);
  EXPECT_THROW(open_particle_file(write_temp("csv.txt", "x,y,z\n1,2,3\n")), Error);
  EXPECT_THROW(open_particle_file(write_temp("gz.txt", "\x1f\x8b\x08rest\n")), Error);
  EXPECT_THROW(open_particle_file(std::string(GRAINFLOW_TEST_OUT) + "/does_not_exist.xyz"), Error);
  try {
    open_particle_file(write_temp("csv.txt", "x,y,z\n1,2,3\n"));
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'x,y,z'"), std::string::npos) << e.what();
  }
}

TEST(MalformedLammps, DataFilesNameTheLine) {
  try {
    read_all(data("malformed/truncated_last_frame.lammpstrj"));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("truncated_last_frame.lammpstrj:21: file ends after 1 of the 2 atoms"), std::string::npos) << msg;
  }
  try {
    read_all(data("malformed/short_line.lammpstrj"));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("short_line.lammpstrj:11: expected 8 columns (id type x y z vx vy vz), got 4"),
              std::string::npos)
        << msg;
  }
}

TEST(MalformedLammps, EveryCaseNamesFileAndLine) {
  const std::string atoms = "ITEM: ATOMS id type x y z radius\n";
  expect_error("m1.lammpstrj", kDumpHead + atoms + "1 1 0.1 0.2 0.3 0.5\n2 1 0.1 abc 0.3 0.5\n", 11,
               "column 4 (y): expected a finite number, got 'abc'");
  expect_error("m2.lammpstrj", kDumpHead + atoms + "1 1 0.1 0.2 0.3 0.5\n2 1 0.1 0.2 0.3 -0.5\n", 11,
               "negative value");
  expect_error("m3.lammpstrj", kDumpHead + atoms + "1 1 0.1 0.2 0.3 0.5\nITEM: TIMESTEP\n", 11,
               "expected atom 2 of 2 (NUMBER OF ATOMS on line 4)");
  expect_error("m4.lammpstrj", kDumpHead + "ITEM: ATOMS id type vx vy\n1 1 0 0\n2 1 0 0\n", 9, "no position columns");
  expect_error("m5.lammpstrj", "ITEM: TIMESTEP\n0\nITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\n" + atoms + "1 1 0 0 0 1\n",
               7, "without a preceding 'ITEM: NUMBER OF ATOMS'");
  expect_error("m6.lammpstrj", kDumpHead + atoms + "1 1 0.1 0.2 0.3 0.5\n2 1 0.1 0.2 0.3 0.5\n0\n", 12,
               "expected an 'ITEM:' header line");
  expect_error("m7.lammpstrj", "ITEM: TIMESTEP\nten\n", 2, "expected the timestep");
  expect_error("m7t.lammpstrj", "ITEM: TIME\ninf\n", 2, "expected the time (one finite number)");
  expect_error("m8.lammpstrj", "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n-3\n", 4, "non-negative integer");
  expect_error("m9.lammpstrj", "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp pp pp\n0 1\n0\n", 7,
               "'lo hi' of the box along y");
  expect_error("m10.lammpstrj", "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ENTRIES\n2\n", 3, "dump local");
  expect_error("m11.lammpstrj", "ITEM: TIMESTEP\n0\nITEM: FOO\n", 3, "unknown header");
  expect_error("m12.lammpstrj", "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\n", 4, "file ends inside the header");
  expect_error("m13.lammpstrj", "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS abc origin\n", 5,
               "general triclinic");
  expect_error("m14.lammpstrj", "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: ATOMS id type xs ys zs\n1 1 0 0 0\n",
               5, "scaled coordinates need 'ITEM: BOX BOUNDS'");
  expect_error("m15.lammpstrj", kDumpHead + "ITEM: ATOMS id type x y z\n1.5 1 0 0 0\n", 10,
               "column 1 (id): expected an integer, got '1.5'");
  expect_error("m16.lammpstrj", kDumpHead + atoms + "1 1 0.1 0.2 inf 0.5\n", 10, "expected a finite number");
}

TEST(MalformedXyz, EveryCaseNamesFileAndLine) {
  const std::string props = "Properties=species:S:1:pos:R:3:radius:R:1\n";
  expect_error("x1.xyz", "2\n" + props + "H 0 0 0 0.5\n", 3, "file ends after 1 of the 2 particle lines");
  try {
    read_all(data("malformed/truncated.xyz"));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("truncated.xyz:4: file ends after 2 of the 3"), std::string::npos) << e.what();
  }
  expect_error("x2.xyz", "2\n" + props + "H 0 0 0 0.5\nH 0 0 0\n", 4,
               "expected 5 columns (species:S:1 pos:R:3 radius:R:1), got 4");
  expect_error("x3.xyz", "1\n" + props + "H 0 0 zero 0.5\n", 3, "column 4 (pos): expected a finite number, got 'zero'");
  expect_error("x4.xyz", "1\n" + props + "H 0 0 0 -1\n", 3, "negative value");
  expect_error("x5.xyz", "1\nx\nH 0 0 0\ntwo\n", 4, "expected the particle count of an XYZ frame");
  expect_error("x5b.xyz", "two\n", 1, "not a particle file");
  expect_error("x6.xyz", "1\nProperties=species:S:1:radius:R:1\nH 0.5\n", 2, "no position property");
  expect_error("x7.xyz", "1\nProperties=species:S:1:pos:R\nH 0 0 0\n", 2, "name:type:count triples");
  expect_error("x8.xyz", "1\nLattice=\"1 0 0 0 1 0 0 0\" Properties=species:S:1:pos:R:3\nH 0 0 0\n", 2,
               "expected 9 numbers, got 8");
  expect_error("x9.xyz", "1\nLattice=\"1 0 0 0 1 0 0 0 1 Properties=species:S:1:pos:R:3\nH 0 0 0\n", 2,
               "unterminated quoted value");
  expect_error("x10.xyz", "1\nplain\nH 0 0 0\n1\nplain\nH 0 0\n", 6, "expected at least 4 columns");
  expect_error("x11.xyz", "2\nplain\nH 0 0 0 1\nH 0 0 0\n", 4, "expected 5 columns");
  expect_error("x13.xyz", "1\nx\n1 0 0 0\n1\nx\nC 0 0 0\n", 6, "not a type number");
  expect_error("x14.xyz", "1\n", 1, "file ends after the particle count");
  expect_error("x15.xyz", "1\nTime=abc Properties=species:S:1:pos:R:3\nH 0 0 0\n", 2, "Time=abc is not a finite number");
  expect_error("x16.xyz", "1\npbc=\"T T\" Lattice=\"1 0 0 0 1 0 0 0 1\"\nH 0 0 0\n", 2, "expected three of T/F");
  expect_error("x17.xyz", "1\nTime=nan Properties=species:S:1:pos:R:3\nH 0 0 0\n", 2, "Time=nan is not a finite number");
}

// A LAMMPS `fix pour` run dumps its empty box first (tests/data/particles/
// lammps_pour_still_running.in made the file): the velocity columns exist from frame 0.
TEST(PourDump, EmptyFirstFrameKeepsItsVelocityColumns) {
  LammpsDumpReader r(data("lammps_pour_still_running.lammpstrj"));
  ParticleFrame f;
  ASSERT_TRUE(r.next(f));
  EXPECT_EQ(f.size(), 0u);
  EXPECT_EQ(f.timestep, 0);
  EXPECT_EQ(f.dim, 3);
  EXPECT_TRUE(f.has_velocity());
  ASSERT_NE(f.column("speed"), nullptr);
  EXPECT_TRUE(f.column("speed")->empty());
  EXPECT_EQ(f.periodic, (std::array<bool, 3>{true, true, false}));  // boundary p p fm
  ASSERT_TRUE(r.next(f));
  EXPECT_EQ(f.size(), 10u);
  ASSERT_NE(f.column("speed"), nullptr);
  EXPECT_GT((*f.column("speed"))[0], 0.0);
}

// The dump ends inside its 7th frame, in the middle of a line, as a file still being
// written does: six complete frames, then TruncatedFrame (an Error naming file:line).
TEST(PourDump, AFileStillBeingWrittenEndsInATruncatedFrame) {
  LammpsDumpReader r(data("lammps_pour_still_running.lammpstrj"));
  ParticleFrame f;
  std::vector<std::size_t> sizes;
  try {
    while (r.next(f)) sizes.push_back(f.size());
    ADD_FAILURE() << "no error at the cut frame";
  } catch (const TruncatedFrame& e) {
    EXPECT_NE(std::string(e.what()).find("lammps_pour_still_running.lammpstrj:172:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("unfinished"), std::string::npos) << e.what();
  }
  EXPECT_EQ(sizes, (std::vector<std::size_t>{0, 10, 20, 20, 24, 24}));
}

// Only a file that ends inside a frame is truncated; a bad line followed by more lines is
// a malformed file.
TEST(PourDump, TruncationIsTheEndOfTheFileOnly) {
  auto kind = [](const std::string& path) {
    try {
      read_all(path);
    } catch (const TruncatedFrame&) {
      return std::string("truncated");
    } catch (const Error&) {
      return std::string("malformed");
    }
    return std::string("fine");
  };
  EXPECT_EQ(kind(data("malformed/truncated_last_frame.lammpstrj")), "truncated");  // ends after 1 of 2 atoms
  EXPECT_EQ(kind(data("malformed/truncated.xyz")), "truncated");
  EXPECT_EQ(kind(data("malformed/short_line.lammpstrj")), "malformed");  // a short line with its '\n'
  const std::string atoms = "ITEM: ATOMS id type x y z radius\n";
  EXPECT_EQ(kind(write_temp("cut_mid_number.lammpstrj", kDumpHead + atoms + "1 1 0.1 0.2 0.3 0.5\n2 1 0.1 0.")),
            "truncated");
  EXPECT_EQ(kind(write_temp("cut_header.lammpstrj", kDumpHead + atoms + "1 1 0.1 0.2 0.3 0.5\n2 1 0.1 0.2 0.3 0.5\n"
                                                                          "ITEM: TIMESTEP\n100\nITEM: NUMBER OF AT")),
            "truncated");
  EXPECT_EQ(kind(write_temp("bad_then_more.lammpstrj", kDumpHead + atoms + "1 1 0.1 0.2 0.3 0.5\n2 1 0.1 0.\n")),
            "malformed");
  EXPECT_EQ(kind(write_temp("cut.xyz", "2\nProperties=species:S:1:pos:R:3\nH 0 0 0\nH 0 0")), "truncated");
  EXPECT_EQ(kind(write_temp("complete_unterminated.xyz", "1\nProperties=species:S:1:pos:R:3\nH 0 0 0")), "fine");
}
