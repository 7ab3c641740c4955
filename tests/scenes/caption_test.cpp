// The frame caption (run/run_loop.hpp frame_caption): the engine's labels after the time,
// N, exposure and stream speed — here the flow's Reynolds and Mach numbers from [medium]
// (Re = U D / ν, Ma = U / c), taken from a real ED runner's snapshot.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "render/snapshot.hpp"
#include "scenes/src/engines/engine_runner.hpp"
#include "scenes/src/engines/engine_table.hpp"
#include "scenes/src/run/run_loop.hpp"
#include "scenes/src/run/scene_catalog.hpp"
#include "scenes/src/scene/run_keys.hpp"
#include "scenes/src/scene/scene.hpp"

using namespace grainflow::scenes;

namespace {

// A 40 × 20 stream of 60 disks at U = 0.2 past an obstacle of D = 6.
const std::string kStream = R"([run]
engine = "ed"
until = 1.0
title = "medium"
[system]
box = [40.0, 20.0]
N = 60
kT = 0.02
U = 0.2
[boundary]
periodic = [false, true]
[boundary.stream]
kind = "dispenser_filter"
[sample]
exposure = 1.0
bins = [4, 2]
)";
const std::string kObstacle = "[boundary.obstacle]\nD = 6.0\nx = 10.0\ny = 10.0\n";

std::string caption_of(const std::string& text, const std::vector<std::string>& overrides = {}) {
  const Scene sc = parse_scene(text, "caption.toml", overrides);
  auto runner = find_engine("ed")->make_runner(sc);
  grainflow::render::Snapshot s;
  runner->snapshot("uniform", s);
  return frame_caption(sc.get(run_keys::title), 1.0, s);
}

std::vector<std::pair<std::string, double>> figures_of(const std::string& text) {
  const Scene sc = parse_scene(text, "caption.toml", {});
  return find_engine("ed")->make_runner(sc)->figures();
}

double figure(const std::vector<std::pair<std::string, double>>& f, const std::string& name) {
  for (const auto& [k, v] : f)
    if (k == name) return v;
  ADD_FAILURE() << "no figure " << name;
  return 0;
}

}  // namespace

TEST(Caption, GivesReynoldsAndMachNumbersOfTheMedium) {
  // Re = 0.2 · 6 / 0.6 = 2, Ma = 0.2 / 1.6 = 0.125.
  const std::string text = kStream + kObstacle + "[medium]\nnu = 0.6\nsound_speed = 1.6\n";
  const std::string c = caption_of(text);
  // (The obstacle took the disks it overlapped: N < 60.) Times in the ED unit τ.
  EXPECT_EQ(c.rfind("medium   t = 0 τ   N = ", 0), 0u) << c;
  EXPECT_NE(c.find("   τ_E = 1 τ   U = 0.2   Re = 2   Ma = 0.125"), std::string::npos) << c;
  const auto f = figures_of(text);
  EXPECT_DOUBLE_EQ(figure(f, "Re"), 2.0);
  EXPECT_DOUBLE_EQ(figure(f, "Ma"), 0.125);
  // Three figures: 0.2 · 6 / 0.69 = 1.739…
  EXPECT_NE(caption_of(text, {"medium.nu=0.69"}).find("Re = 1.74   Ma = 0.125"), std::string::npos);
}

TEST(Caption, SaysOnlyWhatTheSceneGives) {
  // No obstacle: no length for Re, Ma only.
  const std::string c = caption_of(kStream + "[medium]\nnu = 0.6\nsound_speed = 1.6\n");
  EXPECT_EQ(c.find("Re ="), std::string::npos) << c;
  EXPECT_NE(c.find("Ma = 0.125"), std::string::npos) << c;
  // Viscosity only: Re only.
  const std::string r = caption_of(kStream + kObstacle + "[medium]\nnu = 0.6\n");
  EXPECT_NE(r.find("Re = 2"), std::string::npos) << r;
  EXPECT_EQ(r.find("Ma ="), std::string::npos) << r;
  // No stream (a periodic box at rest): neither; no [medium]: neither.
  const std::vector<std::string> at_rest = {"system.U=0.0", "boundary.periodic=[true, true]",
                                            "boundary.stream.kind=\"periodic\""};
  for (const std::string& n : {caption_of(kStream + kObstacle + "[medium]\nnu = 0.6\nsound_speed = 1.6\n", at_rest),
                               caption_of(kStream + kObstacle)}) {
    EXPECT_EQ(n.find("Re ="), std::string::npos) << n;
    EXPECT_EQ(n.find("Ma ="), std::string::npos) << n;
  }
}

TEST(Caption, MediumKeysAreValidated) {
  auto refused = [](const std::string& text) {
    try {
      parse_scene(text, "caption.toml", {});
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(refused(kStream + "[medium]\nnu = 0.0\n").find("medium.nu"), std::string::npos);
  EXPECT_NE(refused(kStream + "[medium]\nsound_speed = -1.0\n").find("medium.sound_speed"), std::string::npos);
  EXPECT_NE(refused(kStream + "[medium]\n").find("gives nothing"), std::string::npos);
  EXPECT_NE(refused(kStream + "[medium]\nc = 1.0\n").find("medium.c"), std::string::npos);
}
