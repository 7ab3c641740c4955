// Colour maps against matplotlib 3.6.3 (reference values printed by
// `/usr/bin/python3 -c "import matplotlib as m; print(m.colormaps['viridis'](k/255))"`:
// matplotlib looks up entry k at t = k/255, where our linear interpolation hits the entry
// exactly) and against Moreland's published cool-warm table (matplotlib _cm._coolwarm_data).
#include "render/layers/colormap.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include "engine/core/error.hpp"

using grainflow::render::Colormap;
using grainflow::render::ColormapId;
using grainflow::render::Rgb;

namespace {

constexpr double kByte = 1.0 / 255.0;

void expect_rgb(const Rgb& c, double r, double g, double b, double tol, const std::string& what) {
  EXPECT_NEAR(c.r, r, tol) << what;
  EXPECT_NEAR(c.g, g, tol) << what;
  EXPECT_NEAR(c.b, b, tol) << what;
}

void expect_hex(const Colormap& m, double t, unsigned hex) {
  const auto c = m.rgba8(t);
  EXPECT_EQ(c.r, (hex >> 16) & 0xff) << m.name() << " t=" << t;
  EXPECT_EQ(c.g, (hex >> 8) & 0xff) << m.name() << " t=" << t;
  EXPECT_EQ(c.b, hex & 0xff) << m.name() << " t=" << t;
  EXPECT_EQ(c.a, 255);
}

struct Ref {
  int k;
  double r, g, b;
};

void check_refs(const char* name, std::initializer_list<Ref> refs) {
  const auto m = Colormap::by_name(name);
  for (const auto& ref : refs)
    expect_rgb(m.rgb(ref.k / 255.0), ref.r, ref.g, ref.b, kByte, std::string(name) + " k=" + std::to_string(ref.k));
}

}  // namespace

TEST(Colormap, ViridisEndsMatchMatplotlibHex) {
  const Colormap v;  // default
  EXPECT_EQ(v.id(), ColormapId::viridis);
  expect_hex(v, 0.0, 0x440154);
  expect_hex(v, 1.0, 0xfde725);
  expect_hex(v, 128 / 255.0, 0x21918c);
  expect_hex(v, 200 / 255.0, 0x70cf57);
}

TEST(Colormap, InteriorValuesMatchMatplotlib) {
  check_refs("viridis", {{51, 0.253935, 0.265254, 0.529983}, {128, 0.127568, 0.566949, 0.550556},
                         {200, 0.440137, 0.811138, 0.340967}});
  check_refs("inferno", {{0, 0.001462, 0.000466, 0.013866}, {51, 0.258234, 0.038571, 0.406485},
                         {128, 0.735683, 0.215906, 0.330245}, {200, 0.985952, 0.615750, 0.025592},
                         {255, 0.988362, 0.998364, 0.644924}});
  check_refs("magma", {{0, 0.001462, 0.000466, 0.013866}, {51, 0.232077, 0.059889, 0.437695},
                       {128, 0.716387, 0.214982, 0.475290}, {200, 0.992785, 0.594891, 0.410283},
                       {255, 0.987053, 0.991438, 0.749504}});
  check_refs("turbo", {{0, 0.189950, 0.071760, 0.232170}, {51, 0.244270, 0.609370, 0.996970},
                       {128, 0.643620, 0.989990, 0.233560}, {200, 0.958010, 0.399580, 0.088310},
                       {255, 0.479600, 0.015830, 0.010550}});
  // matplotlib's coolwarm is piecewise linear between Moreland's 33 points; ours follows
  // Moreland's Msh curve, so they agree to well within a byte.
  check_refs("cool-warm", {{0, 0.229806, 0.298718, 0.753683}, {51, 0.483854, 0.622050, 0.974808},
                           {128, 0.867428, 0.864377, 0.862602}, {200, 0.941728, 0.546413, 0.429707},
                           {255, 0.705673, 0.015556, 0.150233}});
  expect_hex(Colormap::by_name("inferno"), 1.0, 0xfcffa4);
  expect_hex(Colormap::by_name("magma"), 1.0, 0xfcfdbf);
  expect_hex(Colormap::by_name("turbo"), 0.0, 0x30123b);
  expect_hex(Colormap::by_name("cool-warm"), 0.0, 0x3b4cc0);
  expect_hex(Colormap::by_name("cool-warm"), 1.0, 0xb40426);
}

TEST(Colormap, CoolWarmFollowsMorelandTable) {
  // Moreland's CoolWarmFloat33 points at t = 0, 1/4, 1/2, 3/4, 1.
  const Colormap cw(ColormapId::cool_warm);
  expect_rgb(cw.rgb(0.0), 0.2298057, 0.298717966, 0.753683153, 1e-3, "t=0");
  expect_rgb(cw.rgb(0.25), 0.552953156, 0.688929332, 0.995375608, 1e-3, "t=0.25");
  expect_rgb(cw.rgb(0.5), 0.865395197, 0.86541021, 0.865395561, 1e-3, "t=0.5");
  expect_rgb(cw.rgb(0.75), 0.958003065, 0.602842431, 0.481775914, 1e-3, "t=0.75");
  expect_rgb(cw.rgb(1.0), 0.705673158, 0.01555616, 0.150232812, 1e-3, "t=1");
  expect_rgb(cw.rgb(0.5), 0.865, 0.865, 0.865, kByte, "midpoint grey");
}

TEST(Colormap, InterpolatesLinearlyBetweenEntries) {
  const Colormap v;
  const Rgb a = v.rgb(10 / 255.0), b = v.rgb(11 / 255.0), mid = v.rgb(10.25 / 255.0);
  EXPECT_NEAR(mid.r, 0.75 * a.r + 0.25 * b.r, 1e-6);
  EXPECT_NEAR(mid.g, 0.75 * a.g + 0.25 * b.g, 1e-6);
  EXPECT_NEAR(mid.b, 0.75 * a.b + 0.25 * b.b, 1e-6);
}

TEST(Colormap, ClampsAndGreysNaN) {
  const Colormap v;
  expect_hex(v, -3.0, 0x440154);
  expect_hex(v, 7.0, 0xfde725);
  expect_hex(v, std::numeric_limits<double>::infinity(), 0xfde725);
  const Rgb n = v.rgb(std::numeric_limits<double>::quiet_NaN());
  expect_rgb(n, 0.5, 0.5, 0.5, 0.0, "NaN");
}

TEST(Colormap, Tab10IsCategorical) {
  const auto t = Colormap::by_name("tab10");
  EXPECT_TRUE(t.categorical());
  EXPECT_EQ(t.size(), 10);
  const unsigned hex[10] = {0x1f77b4, 0xff7f0e, 0x2ca02c, 0xd62728, 0x9467bd,
                            0x8c564b, 0xe377c2, 0x7f7f7f, 0xbcbd22, 0x17becf};
  for (int k = 0; k < 10; ++k) {
    const auto c = grainflow::render::to_rgba8(t.category(k));
    EXPECT_EQ((c.r << 16) | (c.g << 8) | c.b, hex[k]) << "category " << k;
    const auto w = grainflow::render::to_rgba8(t.category(k + 10));
    EXPECT_EQ((w.r << 16) | (w.g << 8) | w.b, hex[k]) << "wraps at 10";
  }
  const auto neg = grainflow::render::to_rgba8(t.category(-1));
  EXPECT_EQ((neg.r << 16) | (neg.g << 8) | neg.b, hex[9]);
  // No interpolation: t in [k/10, (k+1)/10) is entry k.
  expect_hex(t, 0.15, hex[1]);
  expect_hex(t, 0.19999, hex[1]);
  expect_hex(t, 1.0, hex[9]);
}

TEST(Colormap, ByNameRejectsUnknownAndListsAllowed) {
  EXPECT_EQ(Colormap::by_name("coolwarm").id(), ColormapId::cool_warm);
  try {
    Colormap::by_name("jet");
    FAIL() << "no error";
  } catch (const grainflow::Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("'jet'"), std::string::npos) << msg;
    for (const auto n : Colormap::names()) EXPECT_NE(msg.find(std::string(n)), std::string::npos) << msg;
  }
  EXPECT_EQ(Colormap::names().size(), 6u);
  for (const auto n : Colormap::names()) EXPECT_EQ(Colormap::by_name(n).name(), n);
}

TEST(Colormap, TextureSamplesEndsAndMiddle) {
  const Colormap v;
  const auto tex = v.to_texture(256);
  ASSERT_EQ(tex.size(), 256u);
  EXPECT_EQ(tex.front().r, 0x44);
  EXPECT_EQ(tex.back().g, 0xe7);
  for (int i = 0; i < 256; ++i) {
    const auto c = v.rgba8(i / 255.0);
    EXPECT_EQ(tex[i].r, c.r);
    EXPECT_EQ(tex[i].a, 255);
  }
  EXPECT_EQ(v.to_texture(3)[1].g, v.rgba8(0.5).g);
  EXPECT_EQ(v.to_texture(1).size(), 1u);
  EXPECT_THROW(v.to_texture(0), grainflow::Error);
}

// The compiled tables (render/layers/colormap_tables.cpp) must equal the CSVs in
// assets/colormaps: both are written by assets/colormaps/generate.py.
TEST(Colormap, CompiledTablesMatchCsvAssets) {
  const std::string dir = std::string(GRAINFLOW_TEST_DATA) + "/../../assets/colormaps/";
  for (const auto name : Colormap::names()) {
    std::string file(name);
    for (auto& c : file)
      if (c == '-') c = '_';
    std::ifstream in(dir + file + ".csv");
    ASSERT_TRUE(in) << dir + file + ".csv";
    const auto m = Colormap::by_name(name);
    std::string line;
    int k = 0;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') continue;
      double r, g, b;
      char c1, c2;
      std::istringstream ls(line);
      ASSERT_TRUE(ls >> r >> c1 >> g >> c2 >> b) << file << ": " << line;
      const Rgb got = m.categorical() ? m.category(k) : m.rgb(static_cast<double>(k) / (m.size() - 1));
      expect_rgb(got, r, g, b, 1e-6, file + " entry " + std::to_string(k));
      ++k;
    }
    EXPECT_EQ(k, m.size()) << file;
  }
}
