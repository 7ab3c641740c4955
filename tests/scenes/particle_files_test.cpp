// The particle files of a run end to end (grainflow run → particles.xyz,
// particles.lammpstrj): ids follow the disks (issue 15's acceptance: in disks_box the median
// displacement per id between frames 0.5 apart is below 1 σ), the dump holds the same
// particles as the XYZ file, float32 shrinks the files, and a bad precision is refused.
// ASE, OVITO's conventions and LAMMPS itself are checked by particle_files_check.py.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <sys/wait.h>

#include "engine/io/particle_reader.hpp"
#include "tests/scenes/cli_support.hpp"

namespace fs = std::filesystem;
using grainflow::core::ParticleFrame;

namespace {


const std::string scenes = GRAINFLOW_SCENES_DIR;

std::vector<ParticleFrame> read_all(const fs::path& file) {
  auto reader = grainflow::io::open_particle_file(file.string());
  std::vector<ParticleFrame> out;
  ParticleFrame f;
  while (reader->next(f)) out.push_back(f);
  return out;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? NAN : v[v.size() / 2];
}

// disks_box, one frame every 0.5 time units, both particle files.
const std::string kBox = "run " + scenes +
                         "/disks_box.toml --set run.until=2 --set sample.exposure=0.5 --set output.particles=true "
                         "--set output.lammps_dump=true --set output.png=false --set output.mp4=false "
                         "--set render.size=[64,64] --force";

}  // namespace

TEST(ParticleFiles, IdsFollowTheDisksOfTheBox) {
  const fs::path out = fresh_dir("box");
  const Result r = run(kBox + " -o " + out.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const auto frames = read_all(out / "particles.xyz");
  ASSERT_EQ(frames.size(), 5u);
  const double lx = 100, ly = 100;  // the scene's periodic box
  for (std::size_t k = 0; k + 1 < frames.size(); ++k) {
    const ParticleFrame &a = frames[k], &b = frames[k + 1];
    EXPECT_DOUBLE_EQ(b.time - a.time, 0.5);
    std::map<std::int64_t, std::size_t> row;
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_TRUE(row.emplace(a.id[i], i).second) << "id " << a.id[i] << " twice";
    ASSERT_EQ(b.size(), a.size());
    std::vector<double> by_id, by_row;
    for (std::size_t j = 0; j < b.size(); ++j) {
      auto it = row.find(b.id[j]);
      ASSERT_NE(it, row.end()) << "id " << b.id[j] << " is new in frame " << k + 1 << " of a closed box";
      auto step = [&](const grainflow::Vec3& p, const grainflow::Vec3& q) {
        double dx = q.x() - p.x(), dy = q.y() - p.y();
        dx -= lx * std::round(dx / lx), dy -= ly * std::round(dy / ly);  // nearest periodic image
        return std::hypot(dx, dy);
      };
      by_id.push_back(step(a.position[it->second], b.position[j]));
      by_row.push_back(step(a.position[j], b.position[j]));
    }
    // σ = 1. At kT = 0.02 a disk moves ≈ 0.07 σ in 0.5 (v ≈ 0.2, mean free time ≈ 0.1).
    const double m = median(by_id);
    std::printf("  frames %zu-%zu: median displacement per id %.4f σ (by row %.4f σ)\n", k, k + 1, m, median(by_row));
    EXPECT_LT(m, 1.0);
  }
}

TEST(ParticleFiles, TheDumpHoldsTheXyzParticlesExactly) {
  const fs::path out = fresh_dir("dump");
  const Result r = run(kBox + " --set run.until=1 -o " + out.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const auto xyz = read_all(out / "particles.xyz");
  const auto dump = read_all(out / "particles.lammpstrj");
  ASSERT_EQ(xyz.size(), 3u);
  ASSERT_EQ(dump.size(), xyz.size());
  for (std::size_t k = 0; k < xyz.size(); ++k) {
    const ParticleFrame &a = xyz[k], &b = dump[k];
    EXPECT_EQ(b.dim, 2);
    EXPECT_EQ(b.time, a.time);
    EXPECT_EQ(b.timestep, std::int64_t(k)) << "the ED engine's TIMESTEP is the frame number";
    EXPECT_EQ(b.box_lo.head<2>(), a.box_lo.head<2>());
    EXPECT_EQ(b.box_hi.head<2>(), a.box_hi.head<2>());
    EXPECT_TRUE(b.periodic[0] && b.periodic[1]);
    EXPECT_EQ(b.id, a.id);
    EXPECT_EQ(b.type, a.type);
    EXPECT_EQ(b.position, a.position);
    EXPECT_EQ(b.radius, a.radius);
    EXPECT_EQ(b.velocity, a.velocity);
    ASSERT_NE(a.column("omega_z"), nullptr);
    ASSERT_NE(b.column("omegaz"), nullptr);
    EXPECT_EQ(*b.column("omegaz"), *a.column("omega_z"));
    EXPECT_EQ(*b.column("mass"), *a.column("mass"));
  }
}

TEST(ParticleFiles, Float32ShrinksTheFilesAndStaysClose) {
  const fs::path d64 = fresh_dir("f64"), d32 = fresh_dir("f32");
  ASSERT_EQ(run(kBox + " --set run.until=0.5 -o " + d64.string()).status, 0);
  const Result r = run(kBox + " --set run.until=0.5 --set output.particles_precision=float32 -o " + d32.string());
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* name : {"particles.xyz", "particles.lammpstrj"}) {
    const double ratio = double(fs::file_size(d32 / name)) / double(fs::file_size(d64 / name));
    std::printf("  %s: float32 is %.2f of float64\n", name, ratio);
    EXPECT_LT(ratio, 0.7) << name;
    const auto a = read_all(d64 / name), b = read_all(d32 / name);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t k = 0; k < a.size(); ++k) {
      ASSERT_EQ(a[k].id, b[k].id);
      for (std::size_t i = 0; i < a[k].size(); ++i) {
        EXPECT_EQ(float(b[k].position[i].x()), float(a[k].position[i].x()));
        EXPECT_EQ(float(b[k].velocity[i].y()), float(a[k].velocity[i].y()));
      }
    }
  }
  const fs::path d16 = fresh_dir("f16");
  const Result bad = run(kBox + " --set output.particles_precision=float16 -o " + d16.string());
  EXPECT_EQ(bad.status, 2) << bad.output;
  EXPECT_NE(bad.output.find("output.particles_precision"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("float32"), std::string::npos) << bad.output;
  EXPECT_FALSE(fs::exists(d16)) << "refused before the folder exists";
}

TEST(ParticleFiles, DemIdsAndStepsAreTheEnginesOwn) {
  const fs::path out = fresh_dir("dem");
  const Result r = run("run " + scenes +
                       "/dem_freefall_box.toml --set system.group[0].N=300 --set system.box=[0.01,0.01,0.02] "
                       "--set sample.slab=[0.0,0.01] "
                       "--set run.until=0.004 --set sample.exposure=0.001 --set output.particles=true "
                       "--set output.lammps_dump=true --set output.png=false --set output.mp4=false "
                       "--set render.size=[64,64] --threads 1 -o " + out.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const auto xyz = read_all(out / "particles.xyz");
  const auto dump = read_all(out / "particles.lammpstrj");
  ASSERT_EQ(xyz.size(), 5u);
  ASSERT_EQ(dump.size(), xyz.size());
  for (std::size_t k = 0; k < xyz.size(); ++k) {
    EXPECT_EQ(dump[k].dim, 3);
    EXPECT_EQ(dump[k].timestep, xyz[k].timestep) << "TIMESTEP is the DEM step count";
    if (k > 0) {
      EXPECT_GT(dump[k].timestep, dump[k - 1].timestep);
    }
    EXPECT_EQ(dump[k].id, xyz[0].id) << "the same particles under the same ids in every frame";
    EXPECT_EQ(dump[k].position, xyz[k].position);
    EXPECT_EQ(dump[k].velocity, xyz[k].velocity);
    for (const char* c : {"x", "y", "z"}) {
      ASSERT_NE(dump[k].column(std::string("omega") + c), nullptr);
      EXPECT_EQ(*dump[k].column(std::string("omega") + c), *xyz[k].column(std::string("omega_") + c));
    }
  }
  EXPECT_EQ(xyz[0].id.front(), 1);
  EXPECT_EQ(xyz[0].id.back(), 300);
}
