// The speed of sound study (scenes/src/studies/sound_speed.hpp): the damped-cosine fit
// recovers an exact signal's parameters to round-off and a noisy one's within its stated
// errors about as often as standard errors should; Henderson's adiabatic sound speed has
// the ideal-gas limit and the thermodynamic derivative it claims; a short standing wave run
// end to end gives c within 15 % of Henderson's from both harmonics.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/core/rng.hpp"
#include "scenes/src/run/run_loop.hpp"
#include "scenes/src/run/scene_catalog.hpp"
#include "scenes/src/scene/scene.hpp"
#include "scenes/src/studies/sound_speed.hpp"
#include "tests/scenes/study_csv.hpp"

namespace fs = std::filesystem;
using namespace grainflow::scenes;

namespace {

// a e^{−γt} cos(ωt + φ) sampled every dt from t0, plus white noise of `noise`.
void signal(double a, double gamma, double omega, double phi, double t0, double dt, int n, double noise,
            grainflow::core::Rng* rng, std::vector<double>& t, std::vector<double>& y) {
  t.clear();
  y.clear();
  for (int i = 0; i < n; ++i) {
    t.push_back(t0 + dt * i);
    y.push_back(a * std::exp(-gamma * t.back()) * std::cos(omega * t.back() + phi) + (rng ? noise * rng->normal() : 0.0));
  }
}

}  // namespace

TEST(SoundSpeedStudy, FitRecoversAnExactDampedCosine) {
  // Harmonic 1 of the 128 box: ω = 1.5 π/127, γ = 5e-4; 750 rows every 2 τ (≈ 9 periods).
  std::vector<double> t, y;
  const double omega = 1.5 * std::numbers::pi / 127.0;
  for (double phi : {0.0, 0.7, -2.5, 3.0}) {
    signal(0.02, 5e-4, omega, phi, 2.0, 2.0, 750, 0.0, nullptr, t, y);
    const DampedCosine f = fit_damped_cosine(t, y);
    EXPECT_NEAR(f.omega, omega, 1e-6 * omega) << phi;
    EXPECT_NEAR(f.omega, omega, 1e-10) << phi;
    EXPECT_NEAR(f.gamma, 5e-4, 1e-10) << phi;
    EXPECT_NEAR(f.a, 0.02, 1e-10) << phi;
    EXPECT_NEAR(std::remainder(f.phi - phi, 2 * std::numbers::pi), 0.0, 1e-8) << phi;
    EXPECT_LT(f.rms, 1e-12);
  }
  // A growing start does not fool it: strongly damped, few periods, another spacing.
  signal(1.3, 0.05, 2.0, 1.0, 0.0, 0.1, 200, 0.0, nullptr, t, y);
  const DampedCosine f = fit_damped_cosine(t, y);
  EXPECT_NEAR(f.omega, 2.0, 2e-6);
  EXPECT_NEAR(f.gamma, 0.05, 1e-8);
  EXPECT_THROW(fit_damped_cosine(std::vector<double>(5, 1.0), std::vector<double>(5, 1.0)), grainflow::Error);
}

TEST(SoundSpeedStudy, FitErrorsAreStandardErrors) {
  // 200 noisy realisations (signal to noise 10): ω's error covers the truth ≈ 68 % of the
  // time, and the errors' scatter matches the stated error.
  grainflow::core::Rng rng(17);
  std::vector<double> t, y;
  const double omega = 0.074;
  int within = 0;
  double pull2 = 0;
  const int n = 200;
  for (int k = 0; k < n; ++k) {
    signal(0.02, 1e-3, omega, 0.3, 2.0, 2.0, 500, 0.002, &rng, t, y);
    const DampedCosine f = fit_damped_cosine(t, y);
    const double pull = (f.omega - omega) / f.omega_err;
    within += std::abs(pull) < 1.0 ? 1 : 0;
    pull2 += pull * pull;
  }
  EXPECT_NEAR(double(within) / n, 0.683, 0.08);
  EXPECT_NEAR(std::sqrt(pull2 / n), 1.0, 0.15);
}

TEST(SoundSpeedStudy, HendersonSoundSpeed) {
  // Ideal gas: c² = γ kT/m with γ = 2 in 2D (the first correction is O(η)).
  EXPECT_NEAR(henderson_sound_speed(1e-12, 0.02), std::sqrt(0.04), 1e-11);
  EXPECT_NEAR(henderson_sound_speed(1e-12, 1.0, 4.0), std::sqrt(0.5), 1e-11);
  // c² = (kT/m)[d(ηZ)/dη + Z²], the derivative by central differences.
  for (double eta : {0.1, 0.4, 0.65}) {
    const double h = 1e-6;
    const double d = ((eta + h) * henderson_z(eta + h) - (eta - h) * henderson_z(eta - h)) / (2 * h);
    const double z = henderson_z(eta);
    EXPECT_NEAR(henderson_sound_speed(eta, 0.02), std::sqrt(0.02 * (d + z * z)), 1e-7) << eta;
  }
  // η = 0.65, kT = 0.02: Z = 8.5944, η Z' = 32.78, c = 1.518 (seed 003's Ma labels: ≈ 1.4).
  EXPECT_NEAR(henderson_z(0.65), 1.0528125 / 0.1225, 1e-12);
  EXPECT_NEAR(henderson_sound_speed(0.65, 0.02), 1.5181, 1e-4);
}

TEST(SoundSpeedStudy, StandingWaveRunGivesHendersonsSpeedOfSound) {
  // 32 × 64 (≈ 1700 disks), η = 0.65, kT = 0.02: the lattice melts for 40 τ, then both
  // harmonics are kicked (A = 0.04); 240 τ ≈ 3 periods of harmonic 1 (≈ 83 τ).
  const fs::path dir = fs::path(GRAINFLOW_TEST_OUT) / "sound_speed" / "short";
  fs::remove_all(dir);
  const Scene s = parse_scene(R"([run]
engine = "ed"
until = 280.0
seed = 7
[system]
box = [32.0, 64.0]
area_fraction = 0.65
kT = 0.02
[boundary]
periodic = [true, false]
[boundary.walls]
kind = "slip"
[[phase]]
at = 40.0
wave_vy = [0.04, 0.04]
[sample]
exposure = 40.0
bins = [4, 8]
[output]
png = false
mp4 = false
stats_every = 1.0
[study]
kind = "sound_speed"
henderson_tolerance = 0.15
)",
                              "wave.toml");
  RunOptions opt;
  opt.dir = dir;
  opt.name = "wave";
  opt.quiet = true;
  ASSERT_EQ(run_scene(s, opt), 0);
  auto v = grainflow::scenes::test::study_csv_values(dir / "study.csv");
  const double c_h = v["c_henderson"];
  EXPECT_NEAR(c_h, 1.5181, 1e-3);
  for (const char* c : {"c1", "c2"}) {
    std::printf("%s = %.4f ± %.4f (Henderson %.4f, %+.1f %%)\n", c, v[c], v[std::string(c) + "_err"], c_h,
                100 * (v[c] / c_h - 1));
    EXPECT_NEAR(v[c] / c_h, 1.0, 0.15) << c;
  }
  // The attenuation is hydrodynamic: the second harmonic decays faster.
  EXPECT_GT(v["gamma2"], v["gamma1"]);
  std::ifstream in(dir / "study.json");
  std::stringstream json;
  json << in.rdbuf();
  EXPECT_EQ(json.str().find("\"passed\": false"), std::string::npos) << json.str();
  EXPECT_TRUE(fs::exists(dir / "study.csv"));
  EXPECT_TRUE(fs::exists(dir / "study.png"));
}

TEST(SoundSpeedStudy, SceneChecks) {
  auto refused = [](const std::string& text) {
    try {
      parse_scene(text, "wave.toml", {});
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string base = "[run]\nengine = \"ed\"\nuntil = 10.0\n[system]\nbox = [20.0, 20.0]\narea_fraction = 0.5\n";
  const std::string walls = "[boundary]\nperiodic = [true, false]\n";
  const std::string study = "[study]\nkind = \"sound_speed\"\n";
  EXPECT_NE(refused(base + walls + study).find("exactly one [[phase]] with wave_vy"), std::string::npos);
  EXPECT_NE(refused(base + "[[phase]]\nat = 1.0\nwave_vy = [0.1, 0.0]\n").find("walls in y"), std::string::npos);
  EXPECT_NE(refused(base + walls + "[[phase]]\nat = 1.0\nwave_vy = [0.0, 0.0]\n").find("excites nothing"),
            std::string::npos);
  EXPECT_NE(refused(base + walls + "[[phase]]\nat = 1.0\nwave_vy = [0.1]\n").find("wave_vy"), std::string::npos);
  EXPECT_NE(refused(base + walls + "[[phase]]\nat = 1.0\nwave_vy = [0.1, 0.0]\n" + study + "early = 0.1\n")
                .find("haff_cooling study"),
            std::string::npos);
  EXPECT_EQ(refused(base + walls + "[[phase]]\nat = 1.0\nwave_vy = [0.1, 0.0]\n" + study), "");
}
