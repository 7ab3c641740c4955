// The effective scene (DIR/scene.toml): every key including defaults, in schema order with
// docs; written atomically; reading it back gives the same scene, bit for bit.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "scenes/src/run/scene_catalog.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/scene/schema.hpp"

using namespace grainflow::scenes;
namespace fs = std::filesystem;

namespace {

// The body without the header comment (source and --set lines differ between the copies).
std::string body(const std::string& toml) { return toml.substr(toml.find("\n[")); }

fs::path out_dir(const std::string& name) {
  const fs::path d = fs::path(GRAINFLOW_TEST_OUT) / "effective" / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// Every key of the schema compares equal (TOML text of the value) between a and b.
void expect_same_values(const Scene& a, const Scene& b) {
  ASSERT_EQ(a.engine(), b.engine());
  ASSERT_EQ(a.to_toml().size() > 0, true);
  EXPECT_EQ(body(a.to_toml()), body(b.to_toml()));
}

}  // namespace

TEST(EffectiveScene, HoldsEveryKeyWithDefaultsAndDocs) {
  const Scene s = parse_scene("[run]\nengine = \"ed\"\nuntil = 50\n[system]\nN = 100\n", "t.toml", {"run.seed=7"});
  const std::string t = s.to_toml();
  EXPECT_NE(t.find("# --set run.seed=7\n"), std::string::npos);
  EXPECT_NE(t.find("\n[run]  # what to run"), std::string::npos);
  EXPECT_NE(t.find("\nseed = 7  # seed of the run's one random generator"), std::string::npos) << t;
  EXPECT_NE(t.find("\nuntil = 50.0  # simulated time"), std::string::npos) << t;
  EXPECT_NE(t.find("\nsize = [1280, 720]  # frame size [pixels]"), std::string::npos) << t;
  EXPECT_NE(t.find("\nkT = 0.02  #"), std::string::npos) << t;
  EXPECT_NE(t.find("\n[boundary.stream]"), std::string::npos) << t;
  EXPECT_EQ(t.find("[boundary.obstacle]"), std::string::npos) << t;  // optional, not given
  EXPECT_EQ(t.find("\nsteps ="), std::string::npos) << t;               // optional, not given
  // Every key of every present section is there.
  for (const auto& tbl : s.schema().tables()) {
    if (tbl.kind() != TableKind::Section) continue;
    for (const auto& k : tbl.keys()) {
      if (k.presence != Presence::Defaulted) continue;
      EXPECT_NE(t.find("\n" + k.name + " = "), std::string::npos) << tbl.path() << "." << k.name;
    }
  }
}

TEST(EffectiveScene, RoundTripEd) {
  const std::string text = R"([run]
engine = "ed"
until = 17760
title = "swirl \"A\"\tback\\slash é"
[system]
area_fraction = 0.65
U = 0.30000000000000004
e_t = 1e-300
[boundary]
periodic = [false, true]
[boundary.obstacle]
D = 74
x = 110
y = 220
kind = "noslip_thermal"
[boundary.stream]
kind = "low_density"
[render]
panels = ["particles", "density", "temperature", "streamlines"]
layout = [2, 2]
)";
  const Scene a = parse_scene(text, "a.toml", {"render.size=[1920,1080]"});
  const Scene b = parse_scene(a.to_toml(), "b.toml");
  expect_same_values(a, b);
  EXPECT_EQ(b.get<double>("system.U"), 0.30000000000000004);  // shortest round-trip text keeps the bits
  EXPECT_EQ(b.get<double>("system.e_t"), 1e-300);
  EXPECT_EQ(b.get<std::string>("run.title"), "swirl \"A\"\tback\\slash é");
  EXPECT_EQ(b.get<std::string>("boundary.obstacle.kind"), "noslip_thermal");
  EXPECT_EQ((b.get<std::array<int, 2>>("render.size")), (std::array<int, 2>{1920, 1080}));
  EXPECT_EQ((b.get<std::array<bool, 2>>("boundary.periodic")), (std::array<bool, 2>{false, true}));
}

TEST(EffectiveScene, RoundTripDemWithArrayOfTables) {
  const std::string text = R"([run]
engine = "dem"
until = 1.5
seed = 42
[system]
box = [0.02, 0.02, 0.04]
dt = 1e-6
[[system.group]]
N = 100
radius = 0.001
[[system.group]]
N = 50
radius = 0.0015
[system.vdw]
A = 6.5e-20
[sample]
plane = "xy"
)";
  const Scene a = parse_scene(text, "a.toml");
  const Scene b = parse_scene(a.to_toml(), "b.toml");
  expect_same_values(a, b);
  EXPECT_EQ(b.count("system.group"), 2u);
  EXPECT_EQ(b.get<double>("system.group[1].radius"), 0.0015);
  EXPECT_EQ(b.get<double>("system.dt"), 1e-6);
  EXPECT_EQ(b.get<std::string>("sample.plane"), "xy");
}

TEST(EffectiveScene, WrittenAtomicallyAndLoadable) {
  const fs::path dir = out_dir("written");
  const Scene a = parse_scene("[run]\nengine = \"ed\"\nuntil = 5.0\n[system]\nn = 0.83\n", "a.toml");
  write_effective_scene(a, dir / "scene.toml");
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1u);  // no temporary left behind
  const Scene b = load_scene(dir / "scene.toml");
  expect_same_values(a, b);
  EXPECT_EQ(b.source(), dir / "scene.toml");
  EXPECT_THROW(write_effective_scene(a, "/etc/passwd/scene.toml"), grainflow::Error);
}
