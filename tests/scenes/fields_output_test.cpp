// output.fields: a frame's VTI holds, for a bin, the values the binning code computes for it
// (read back from our own file: the appended raw arrays located by their offsets), and the
// .npy the same; the values are also checked by hand for three disks in one bin.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "engine/core/binning.hpp"
#include "scenes/src/engines/field_snapshot.hpp"
#include "scenes/src/outputs/output_table.hpp"
#include "scenes/src/outputs/run_record.hpp"
#include "scenes/src/run/scene_catalog.hpp"
#include "scenes/src/scene/scene.hpp"

namespace fs = std::filesystem;

namespace grainflow::scenes {
namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The `components` doubles of bin b of the appended array called `name` in a VTI we wrote.
std::vector<double> vti_value(const std::string& vti, const std::string& name, std::size_t b, int components) {
  std::smatch m;
  const std::regex decl("Name=\"" + name + "\" NumberOfComponents=\"([0-9]+)\" format=\"appended\" offset=\"([0-9]+)\"");
  if (!std::regex_search(vti, m, decl)) throw std::runtime_error("no array " + name);
  EXPECT_EQ(std::stoi(m[1].str()), components) << name;
  const std::size_t data = vti.find("<AppendedData encoding=\"raw\">");
  const std::size_t start = vti.find('_', data) + 1 + std::stoull(m[2].str());
  std::uint64_t bytes = 0;
  std::memcpy(&bytes, vti.data() + start, 8);
  EXPECT_EQ(bytes % (8 * components), 0u);
  std::vector<double> out(components);
  std::memcpy(out.data(), vti.data() + start + 8 + 8 * components * b, 8 * components);
  return out;
}

TEST(FieldsOutput, AVtiBinHoldsTheBinningCodesValues) {
  const fs::path dir = fs::path(GRAINFLOW_TEST_OUT) / "fields_output";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const Scene scene = parse_scene(R"([run]
engine = "ed"
until = 1.0
[system]
box = [8.0, 8.0]
N = 3
kT = 1.0
[output]
fields = true
)");
  // Three unit disks in bin (1, 2) of a 4 × 4 grid of 2 × 2 bins, one in bin (3, 0).
  core::ParticleFrame f;
  f.dim = 2;
  f.position = {{2.5, 4.5, 0}, {3.0, 5.0, 0}, {3.5, 5.5, 0}, {7.0, 1.0, 0}};
  f.velocity = {{1, 0, 0}, {0, 1, 0}, {-1, -1, 0}, {0.5, 0.5, 0}};
  f.radius = {0.5, 0.5, 0.5, 0.5};
  f.id = {1, 2, 3, 4};
  f.type = {1, 1, 1, 1};
  core::BinningOptions opt;
  opt.grid.nx = opt.grid.ny = 4;
  opt.grid.lo = Vec2(0, 0);
  opt.grid.hi = Vec2(8, 8);
  const core::BinnedFields binned = core::bin_frame(f, opt);
  render::Snapshot s;
  s.dim = 2;
  s.lo = {0, 0, 0};
  s.hi = {8, 8, 0};
  s.time = 0.75;
  set_binned_fields(binned, s, {}, render::FieldExposure{0.25, 0.75, 1, {0, 1}, std::nullopt});

  const OutputEntry* entry = nullptr;
  for (const auto& o : outputs())
    if (o.name == "fields") entry = &o;
  ASSERT_NE(entry, nullptr);
  OutputContext ctx{scene, dir, "case", {}, [](std::string_view) {}, std::nullopt};
  auto out = entry->open_data(ctx);
  ASSERT_NE(out, nullptr);
  const RunRecord record = make_run_record(scene);
  out->start(record);
  out->frame(7, s);
  out->finish(record);

  const std::string vti = slurp(dir / "fields" / "frame_000007.vti");
  ASSERT_FALSE(vti.empty());
  EXPECT_NE(vti.find("WholeExtent=\"0 4 0 4 0 1\" Origin=\"0 0 0\" Spacing=\"2 2 1\""), std::string::npos);
  const std::size_t b = opt.grid.index(1, 2);
  // The binning code's values for the bin ...
  EXPECT_EQ(vti_value(vti, "number_density", b, 1)[0], binned.density.values[b]);
  EXPECT_EQ(vti_value(vti, "kT", b, 1)[0], binned.temperature->values[b]);
  EXPECT_EQ(vti_value(vti, "mean_speed", b, 1)[0], binned.mean_speed->values[b]);
  EXPECT_EQ(vti_value(vti, "area_fraction", b, 1)[0], binned.fraction->values[b]);
  const auto v = vti_value(vti, "mean_velocity", b, 3);
  EXPECT_EQ(v[0], binned.mean_velocity->values[b].x());
  EXPECT_EQ(v[1], binned.mean_velocity->values[b].y());
  // ... which are, by hand: 3 disks in 4 σ², <v> = 0, kT = Σ m|v|²/(2·3) = 4/6.
  EXPECT_DOUBLE_EQ(vti_value(vti, "number_density", b, 1)[0], 0.75);
  EXPECT_DOUBLE_EQ(vti_value(vti, "kT", b, 1)[0], 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(vti_value(vti, "mean_speed", b, 1)[0], (2.0 + std::sqrt(2.0)) / 3.0);
  EXPECT_NEAR(v[0], 0.0, 1e-15);
  EXPECT_NEAR(v[1], 0.0, 1e-15);
  EXPECT_EQ(v[2], 0.0);
  // An empty bin: density 0 (a measurement), kT undefined (NaN), no samples.
  const std::size_t e = opt.grid.index(0, 0);
  EXPECT_EQ(vti_value(vti, "number_density", e, 1)[0], 0.0);
  EXPECT_TRUE(std::isnan(vti_value(vti, "kT", e, 1)[0]));
  EXPECT_EQ(vti_value(vti, "open_fraction", e, 1)[0], 1.0);

  const std::string pvd = slurp(dir / "fields.pvd");
  EXPECT_NE(pvd.find("<DataSet timestep=\"0.75\" group=\"\" part=\"0\" file=\"fields/frame_000007.vti\"/>"),
            std::string::npos) << pvd;
  // The .npy: a (ny, nx) structured array whose records start with the bin centre.
  const std::string npy = slurp(dir / "fields" / "frame_000007.npy");
  ASSERT_GT(npy.size(), 10u);
  EXPECT_EQ(npy.substr(0, 6), "\x93NUMPY");
  const std::size_t header = 10 + std::uint8_t(npy[8]) + 256 * std::uint8_t(npy[9]);
  EXPECT_EQ(header % 64, 0u);
  EXPECT_NE(npy.find("'shape': (4, 4)"), std::string::npos);
  EXPECT_EQ((npy.size() - header) % 16, 0u);
  const std::size_t bytes_per_bin = (npy.size() - header) / 16;
  double x = 0, y = 0, n = 0;
  std::memcpy(&x, npy.data() + header + bytes_per_bin * b, 8);
  std::memcpy(&y, npy.data() + header + bytes_per_bin * b + 8, 8);
  std::memcpy(&n, npy.data() + header + bytes_per_bin * b + 24, 8);
  EXPECT_EQ(x, 3.0);
  EXPECT_EQ(y, 5.0);
  EXPECT_EQ(n, binned.density.values[b]);
}

}  // namespace
}  // namespace grainflow::scenes
