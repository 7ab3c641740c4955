// The rules of the application wing (ARCHITECTURE.md): the schema takes its allowed names
// from the tables that honour them, and every declared key is consumed — small scenes of
// each engine run through the run loop in-process, and every key of each engine's schema
// must have been read through its handle (pbrt-v4 reports unused parameters; here a key
// that nothing reads fails the suite).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "engine/dem/contact_params.hpp"
#include "render/layers/colormap.hpp"
#include "render/panel_layout.hpp"
#include "scenes/src/engines/engine_runner.hpp"
#include "scenes/src/engines/engine_table.hpp"
#include "scenes/src/outputs/output_table.hpp"
#include "scenes/src/run/run_loop.hpp"
#include "scenes/src/run/scene_catalog.hpp"
#include "scenes/src/studies/study_table.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/scene/schema.hpp"

namespace fs = std::filesystem;
using namespace grainflow::scenes;

namespace {

std::vector<std::string> strings(std::span<const std::string_view> names) { return {names.begin(), names.end()}; }

const KeySpec& key(std::string_view engine, std::string_view path) {
  const KeySpec* k = schema_for_engine(engine).find_key(path);
  if (!k) throw std::logic_error("no key " + std::string(path));
  return *k;
}

// Every key of `schema` (dotted, no indices) that is not in `read`.
std::vector<std::string> unread_keys(const Schema& schema, const std::set<std::string>& read) {
  std::vector<std::string> out;
  for (const auto& t : schema.tables())
    for (const auto& k : t.keys())
      if (!read.count(t.path() + "." + k.name)) out.push_back(t.path() + "." + k.name);
  return out;
}

fs::path fresh(const std::string& name) {
  const fs::path d = fs::path(GRAINFLOW_TEST_OUT) / "app_tables" / name;
  fs::remove_all(d);
  return d;
}

// Small frames, a short video: every output on in at least one case.
const std::string kRender = "[render]\nsize = [64, 48]\nmsaa = 0\n";

const std::string kEd = R"([run]
engine = "ed"
until = 2.0
title = "keys"
[system]
box = [24.0, 24.0]
kT = 1.0
[sample]
exposure = 1.0
bins = [4, 4]
)";

const std::string kDem = R"([run]
engine = "dem"
until = 2.0e-3
[system]
box = [0.01, 0.01, 0.01]
[[system.group]]
N = 20
radius = 5.0e-4
[sample]
exposure = 1.0e-3
bins = [4, 4]
)";

std::string steps_instead_of_until(std::string text) {
  const std::string until = "until = 2.0e-3\n";
  return text.replace(text.find(until), until.size(), "steps = 5\n");
}

struct Case {
  std::string text;
  std::vector<std::string> overrides;
};

std::vector<Case> cases(const fs::path& dir) {
  // A two-particle file for system.initial.kind = "file".
  fs::create_directories(dir);
  const fs::path xyz = dir / "pair.xyz";
  std::ofstream(xyz) << "2\nLattice=\"0.01 0 0 0 0.01 0 0 0 0.01\" Properties=species:S:1:pos:R:3:radius:R:1\n"
                        "1 0.003 0.005 0.005 5e-4\n1 0.007 0.005 0.005 5e-4\n";
  // Three disks in the 24 × 24 box, for the ED engine.
  const fs::path disks = dir / "disks.xyz";
  std::ofstream(disks) << "3\nProperties=species:S:1:pos:R:3:radius:R:1:velo:R:3:omega:R:1\n"
                          "1 4 4 0 0.5 0.1 0 0 0\n1 12 12 0 0.5 0 0.1 0 0.2\n1 20 6 0 0.5 -0.1 0 0 0\n";
  return {
      {kEd + kRender, {"system.area_fraction=0.3", "output.particles=true", "render.range=[0.0, 2.0]"}},
      {kEd + kRender, {"system.n=0.2", "output.mp4=false", "system.mu=0.3", "output.stats_every=0.5"}},
      {kEd + kRender, {"system.n=0.2", "output.mp4=false", "render.layout=[2, 2]",
                       "render.panels=[\"density\", \"temperature\", \"speed\", \"streamlines\"]",
                       "render.ranges.density=[0.0, 1.0]", "render.ranges.temperature=[0.5, 1.5]",
                       "render.ranges.speed=[0.0, 2.0]", "render.ranges.streamlines=[0.0, 1.0]"}},
      {kEd + kRender, {"system.initial.kind=\"file\"", "system.initial.file=\"" + disks.string() + "\"",
                       "system.initial.frame=0", "output.mp4=false", "output.png=false"}},
      {kEd + kRender + "[boundary.obstacle]\nD = 4.0\nx = 12.0\ny = 12.0\n",
       {"system.N=60", "boundary.periodic=[false, true]", "boundary.stream.kind=\"dispenser_filter\"", "system.U=0.5",
        "output.png=false", "output.fields=true"}},
      {kEd + kRender, {"system.N=40", "boundary.periodic=[false, true]", "boundary.stream.kind=\"low_density\"",
                       "system.U=0.5", "output.png=false", "output.mp4=false"}},
      // The thermostat's keys are read only when [thermostat] is on.
      {kEd + kRender + "[thermostat]\nkind = \"single\"\nT = 1.2\ntau = 1.0\ntau_v = 2.0\nbin = 4.0\n",
       {"system.area_fraction=0.3", "output.png=false", "output.mp4=false"}},
      // The walls' and the phases' keys are read only with walls in y and [[phase]] tables.
      {kEd + kRender + "[boundary.walls]\nkind = \"noslip_thermal\"\nkT = 1.0\nU = [-0.1, 0.1]\n"
                       "[boundary.obstacle]\nD = 4.0\nx = 12.0\ny = 12.0\nkind = \"noslip_flip\"\n"
                       "[thermostat]\n"
                       "[[phase]]\nat = 0.0\nthermostat = false\n"
                       "[[phase]]\nat = 0.5\nlabel = \"inelastic\"\ne = 0.9\nobstacle_r = 0.8\nobstacle_kind = \"slip\"\n"
                       "thermostat = true\nthermostat_T = 1.5\n",
       {"system.area_fraction=0.3", "boundary.periodic=[true, false]", "system.tau_tc=1e-4", "output.png=false",
        "output.mp4=false"}},
      {kEd + kRender + "[boundary.walls]\nkind = \"noslip_flip\"\nr = 0.9\n",
       {"system.area_fraction=0.3", "boundary.periodic=[true, false]", "output.png=false", "output.mp4=false"}},
      // The studies' keys are read only when [study] chooses them.
      // (Dense enough that the lattice collides in the first stats window.)
      {kEd + kRender + "[study]\nkind = \"haff_cooling\"\nearly = 1.0\ntolerance = 0.5\n",
       {"system.area_fraction=0.6", "system.e=0.5", "system.tau_tc=1e-4", "output.stats_every=0.1",
        "output.png=false", "output.mp4=false"}},
      {kEd + kRender + "[thermostat]\nT = 1.0\n[study]\nkind = \"thermostat_hold\"\ntarget_kT = 1.0\nsettle = 0.5\n"
                       "hold_tolerance = 0.5\n",
       {"system.area_fraction=0.3", "system.e=0.9", "system.tau_tc=1e-4", "output.stats_every=0.05",
        "output.png=false", "output.mp4=false"}},
      // The medium's keys are read only with [medium].
      {kEd + kRender + "[boundary.obstacle]\nD = 4.0\nx = 12.0\ny = 12.0\n[medium]\nnu = 0.7\nsound_speed = 1.5\n",
       {"system.N=60", "system.U=0.5", "output.png=false", "output.mp4=false"}},
      // The standing wave of the sound_speed study (phase.wave_vy): ≈ 1 period of harmonic 1.
      {kEd + kRender + "[boundary.walls]\nkind = \"slip\"\n[[phase]]\nat = 1.0\nwave_vy = [0.3, 0.2]\n"
                       "[study]\nkind = \"sound_speed\"\nfit_span = 18.0\nhenderson_tolerance = 10.0\n",
       {"system.area_fraction=0.3", "boundary.periodic=[true, false]", "run.until=20.0", "output.stats_every=0.2",
        "output.png=false", "output.mp4=false"}},
      // The couette study (two exposures after skip = 0) and the drag study.
      {kEd + kRender + "[boundary.walls]\nkind = \"noslip_thermal\"\nU = [-0.5, 0.5]\n"
                       "[study]\nkind = \"couette\"\nskip = 0.0\nbulk_fraction = 0.5\n",
       {"system.area_fraction=0.3", "boundary.periodic=[true, false]", "output.png=false", "output.mp4=false"}},
      {kEd + kRender + "[boundary.obstacle]\nD = 4.0\nx = 12.0\ny = 12.0\n[study]\nkind = \"drag\"\ntransient = 0.5\n",
       {"system.N=60", "system.U=0.5", "output.stats_every=0.05", "output.png=false", "output.mp4=false"}},
      {kDem + kRender, {"system.initial.kind=\"lattice\"", "output.particles=true", "output.fields=true", "render.color_by=\"group\"",
                        "render.layout=[2, 1]", "render.panels=[\"density\", \"temperature\"]",
                        "render.ranges.density=[0.0, 1.0]"}},
      {kDem + kRender + "[system.vdw]\nA = 1.0e-19\n",
       {"system.initial.kind=\"file\"", "system.initial.file=\"" + xyz.string() + "\"", "system.group[0].N=2",
        "output.pair_csv=true", "output.png=false", "system.dt=1.0e-6"}},
      {steps_instead_of_until(kDem) + kRender, {"output.png=false", "output.mp4=false"}},
      // output.particles_precision is read only when a particle file is written.
      {kDem + kRender, {"output.lammps_dump=true", "output.particles_precision=\"float32\"", "output.png=false",
                        "output.mp4=false"}},
  };
}

}  // namespace

TEST(AppTables, SchemaNamesComeFromTheTablesThatHonourThem) {
  for (const auto& e : engines()) {
    EXPECT_EQ(key(e.name, "render.panels").choices, strings(grainflow::render::panel_names()));
    EXPECT_EQ(key(e.name, "render.colormap").choices, strings(grainflow::render::Colormap::names()));
    EXPECT_EQ(key(e.name, "render.color_by").choices, e.colour_attributes());
    EXPECT_EQ(key(e.name, "run.engine").choices, engine_names());
  }
  EXPECT_EQ(key("dem", "system.contact.normal").choices, grainflow::dem::normal_model_names());
  EXPECT_EQ(key("dem", "system.contact.tangential").choices, grainflow::dem::tangential_model_names());
  // [study] kind offers the studies of the engine, from the study table.
  std::vector<std::string> ed_studies;
  for (const auto& st : grainflow::scenes::studies())
    if (st.engine == "ed") ed_studies.emplace_back(st.name);
  EXPECT_EQ(key("ed", "study.kind").choices, ed_studies);
  // A 2D engine offers no vz; the 3D one does.
  const auto ed = find_engine("ed")->colour_attributes(), dem = find_engine("dem")->colour_attributes();
  EXPECT_EQ(std::count(ed.begin(), ed.end(), "vz"), 0);
  EXPECT_EQ(std::count(dem.begin(), dem.end(), "vz"), 1);
}

TEST(AppTables, EveryOutputRowOpensOneKindOfOutput) {
  std::set<std::string_view> names;
  for (const auto& o : outputs()) {
    EXPECT_NE(o.open_image == nullptr, o.open_data == nullptr) << o.name;
    EXPECT_TRUE(names.insert(o.name).second) << o.name;
  }
  EXPECT_EQ(outputs().back().name, "run.json");  // finished last, recording the others done
}

TEST(AppTables, UnreadKeysAreFound) {
  // The check below can fail: with only run.engine read, everything else is reported.
  const auto unread = unread_keys(schema_for_engine("ed"), {"run.engine"});
  EXPECT_GT(unread.size(), 20u);
  EXPECT_EQ(std::count(unread.begin(), unread.end(), "run.engine"), 0);
  EXPECT_EQ(std::count(unread.begin(), unread.end(), "system.kT"), 1);
}

TEST(AppTables, EveryDeclaredKeyIsReadBySomething) {
  const fs::path dir = fresh("declared");
  std::map<std::string, std::set<std::string>> read;
  int n = 0;
  for (const auto& c : cases(dir)) {
    const Scene s = parse_scene(c.text, "case.toml", c.overrides);
    RunOptions opt;
    opt.dir = dir / ("case" + std::to_string(n++));
    opt.name = "case";
    opt.quiet = true;
    // As `grainflow run` does before it runs a scene (which reads output.video_seconds).
    (void)auto_fps_override(s);
    ASSERT_EQ(run_scene(s, opt), 0);
    for (auto& k : s.keys_read()) read[s.engine()].insert(k);
  }
  for (const auto& e : engines()) {
    const auto unread = unread_keys(schema_for_engine(e.name), read[std::string(e.name)]);
    std::string list;
    for (const auto& k : unread) list += " " + k;
    EXPECT_TRUE(unread.empty()) << e.name << ": declared but read by nothing:" << list;
  }
}

// stats.json: every column a runner reports — the engines' own and every agent's, over
// cases that attach every agent — has a unit and a definition, and each name is unique.
// A column added without them fails here.
TEST(AppTables, EveryStatsColumnIsDocumented) {
  const fs::path dir = fresh("stats_docs");
  std::set<std::string> seen;
  for (const auto& c : cases(dir)) {
    const Scene s = parse_scene(c.text, "case.toml", c.overrides);
    const auto runner = find_engine(s.engine())->make_runner(s);
    std::set<std::string> names;
    for (const auto& col : runner->stats_columns()) {
      EXPECT_FALSE(col.name.empty());
      EXPECT_TRUE(names.insert(col.name).second) << s.engine() << ": column " << col.name << " twice";
      EXPECT_FALSE(col.unit.empty()) << s.engine() << ": column " << col.name << " has no unit";
      EXPECT_GT(col.definition.size(), 10u) << s.engine() << ": column " << col.name << " has no definition";
      seen.insert(s.engine() + "." + col.name);
    }
  }
  // The cases reach the agents' columns (else the check above would miss them).
  for (const char* name : {"ed.drag_x", "ed.thermostat_power", "ed.inserted", "ed.pressure", "dem.wall_force_bottom_z"})
    EXPECT_EQ(seen.count(name), 1u) << name;
  // The run writes them, time first, in stats.csv's order.
  const Scene s = parse_scene(cases(dir)[6].text, "case.toml", cases(dir)[6].overrides);
  RunOptions opt;
  opt.dir = dir / "run";
  opt.name = "case";
  opt.quiet = true;
  ASSERT_EQ(run_scene(s, opt), 0);
  std::ifstream csv(opt.dir / "stats.csv");
  std::string header;
  std::getline(csv, header);
  std::ifstream in(opt.dir / "stats.json");
  std::stringstream json;
  json << in.rdbuf();
  std::size_t at = 0;
  std::stringstream cols(header);
  for (std::string name; std::getline(cols, name, ',');) {
    const std::size_t p = json.str().find("\"name\": \"" + name + "\"", at);
    EXPECT_NE(p, std::string::npos) << name << " is not documented in stats.json (in order)";
    if (p != std::string::npos) at = p;
  }
  EXPECT_NE(header.find("thermostat_power"), std::string::npos);
}
