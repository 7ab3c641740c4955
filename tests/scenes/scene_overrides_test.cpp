// `--set section.key=value` overrides: TOML values, plain strings, arrays, array-of-table
// elements, and the same validation as the file, with the --set named as the location.
#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "scenes/src/run/scene_catalog.hpp"
#include "scenes/src/scene/scene.hpp"

using namespace grainflow::scenes;

namespace {

constexpr const char* kEd = R"([run]
engine = "ed"
until = 100.0
[system]
area_fraction = 0.65
)";

std::vector<SceneIssue> issues_of(std::string_view text, const std::vector<std::string>& overrides) {
  try {
    parse_scene(text, "t.toml", overrides);
  } catch (const SceneError& e) {
    return e.issues();
  }
  return {};
}

}  // namespace

TEST(SceneOverrides, ScalarsArraysAndStrings) {
  const Scene s = parse_scene(kEd, "t.toml",
                              {"run.seed=3", "render.size=[640,480]", "boundary.obstacle.kind=\"noslip_flip\"",
                               "boundary.obstacle.x=200", "boundary.obstacle.y = 220.5", "run.title=flow past a disk",
                               "render.backend=osmesa", "system.e=0.9"});
  EXPECT_EQ(s.get<std::int64_t>("run.seed"), 3);
  EXPECT_EQ((s.get<std::array<int, 2>>("render.size")), (std::array<int, 2>{640, 480}));
  EXPECT_EQ(s.get<std::string>("boundary.obstacle.kind"), "noslip_flip");
  EXPECT_EQ(s.get<double>("boundary.obstacle.x"), 200.0);
  EXPECT_EQ(s.get<double>("boundary.obstacle.y"), 220.5);
  EXPECT_EQ(s.get<double>("boundary.obstacle.D"), 74.0);  // default inside the table --set created
  EXPECT_EQ(s.get<std::string>("run.title"), "flow past a disk");  // unquoted string
  EXPECT_EQ(s.get<std::string>("render.backend"), "osmesa");
  EXPECT_EQ(s.get<double>("system.e"), 0.9);
  EXPECT_EQ(s.overrides().size(), 8u);
}

TEST(SceneOverrides, LaterOverrideWinsAndValueMayContainEquals) {
  const Scene s = parse_scene(kEd, "t.toml", {"run.seed=3", "run.seed=4", "run.title=a = b"});
  EXPECT_EQ(s.get<std::int64_t>("run.seed"), 4);
  EXPECT_EQ(s.get<std::string>("run.title"), "a = b");
}

TEST(SceneOverrides, UnquotedEngineSwitchesSchema) {
  const Scene s = parse_scene("[run]\nengine = \"ed\"\nsteps = 10\n[[system.group]]\nN = 10\n", "t.toml",
                              {"run.engine=dem"});
  EXPECT_EQ(s.engine(), "dem");
  EXPECT_EQ(s.count("system.group"), 1u);
}

TEST(SceneOverrides, WrongTypeNamesTheSet) {
  const auto v = issues_of(kEd, {"run.seed=abc"});
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].location, "--set run.seed=abc");
  EXPECT_EQ(v[0].key, "run.seed");
  EXPECT_NE(v[0].message.find("run.seed = \"abc\" has the wrong type (a string); allowed: an integer"),
            std::string::npos)
      << v[0].message;
  const auto w = issues_of(kEd, {"render.size=[640]"});
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].location, "--set render.size=[640]");
  EXPECT_NE(w[0].message.find("has 1 elements"), std::string::npos);
  const auto x = issues_of(kEd, {"render.size=[8,480]"});
  ASSERT_EQ(x.size(), 1u);
  EXPECT_NE(x[0].message.find("render.size[0] (w) = 8 is out of range"), std::string::npos);
}

TEST(SceneOverrides, UnknownKeyFailsNamingKey) {
  const auto v = issues_of(kEd, {"run.sed=3"});
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].location, "--set run.sed=3");
  EXPECT_EQ(v[0].key, "run.sed");
  EXPECT_NE(v[0].message.find("unknown key run.sed = 3; did you mean run.seed?"), std::string::npos) << v[0].message;
  const auto w = issues_of(kEd, {"rnu.seed=3"});
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].message.find("unknown section [rnu]; did you mean [run]?"), std::string::npos) << w[0].message;
}

TEST(SceneOverrides, MalformedValueOrKey) {
  const auto v = issues_of(kEd, {"render.size=[640,"});
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0].location, "--set render.size=[640,");
  EXPECT_NE(v[0].message.find("is not a valid TOML value"), std::string::npos) << v[0].message;
  EXPECT_THROW(parse_scene(kEd, "t.toml", {"run.seed"}), grainflow::Error);
  EXPECT_THROW(parse_scene(kEd, "t.toml", {"=3"}), grainflow::Error);
  EXPECT_THROW(parse_scene(kEd, "t.toml", {"run..seed=3"}), grainflow::Error);
  const auto w = issues_of(kEd, {"run.seed=1", "run.seed.x=3"});
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].message.find("run.seed is an integer, not a table"), std::string::npos) << w[0].message;
}

TEST(SceneOverrides, MissingRequiredKeyInTableCreatedBySet) {
  const auto v = issues_of(kEd, {"boundary.obstacle.D=10"});
  ASSERT_EQ(v.size(), 2u);  // x and y
  EXPECT_EQ(v[0].location, "--set boundary.obstacle.D=10");
  EXPECT_NE(v[0].message.find("missing required key boundary.obstacle.x"), std::string::npos) << v[0].message;
}

TEST(SceneOverrides, ArrayElementsAndArrayOfTables) {
  const std::string dem = "[run]\nengine = \"dem\"\nsteps = 10\n[[system.group]]\nN = 10\n";
  const Scene s = parse_scene(dem + "[render]\nsize = [640, 480]\n", "t.toml",
                              {"system.group[0].N=20", "system.group[1].radius=0.002", "render.size[0]=800"});
  EXPECT_EQ(s.count("system.group"), 2u);
  EXPECT_EQ(s.get<std::int64_t>("system.group[0].N"), 20);
  EXPECT_EQ(s.get<double>("system.group[1].radius"), 0.002);
  EXPECT_EQ((s.get<std::array<int, 2>>("render.size")), (std::array<int, 2>{800, 480}));
  // An array the file does not give (a default) is set whole, not element by element.
  const auto v = issues_of(dem, {"render.size[0]=800"});
  ASSERT_EQ(v.size(), 1u);
  EXPECT_NE(v[0].message.find("render.size is not in the scene"), std::string::npos) << v[0].message;
}

TEST(SceneOverrides, ArrayOfTablesNeedsIndex) {
  const std::string dem = "[run]\nengine = \"dem\"\nsteps = 10\n[[system.group]]\nN = 10\n";
  const auto v = issues_of(dem, {"system.group.N=3"});
  ASSERT_EQ(v.size(), 1u);
  EXPECT_NE(v[0].message.find("system.group is an array of tables; allowed: system.group[i].N"), std::string::npos)
      << v[0].message;
  const auto w = issues_of(dem, {"system.group[5].N=3"});
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].message.find("system.group[5] does not exist; system.group has 1 elements"), std::string::npos)
      << w[0].message;
}
