#include "render/layers/colormap.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "engine/core/error.hpp"
#include "render/layers/colormap_tables.hpp"

namespace grainflow::render {
namespace {

// The names are the generated tables' own: one list, in ColormapId order. Built on first
// use, after the tables (another translation unit) are initialised.
const std::array<std::string_view, colormap_tables::kCount>& table_names() {
  static const std::array<std::string_view, colormap_tables::kCount> n = [] {
    std::array<std::string_view, colormap_tables::kCount> out;
    for (int i = 0; i < colormap_tables::kCount; ++i) out[std::size_t(i)] = colormap_tables::all[i].name;
    return out;
  }();
  return n;
}

const colormap_tables::Table& table(ColormapId id) { return colormap_tables::all[static_cast<int>(id)]; }

std::uint8_t to_byte(float v) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

}  // namespace

Colormap::Colormap(ColormapId id) : id_(id) {}

Colormap Colormap::by_name(std::string_view name) {
  const auto& names = table_names();
  for (std::size_t i = 0; i < names.size(); ++i)
    if (name == names[i]) return Colormap(static_cast<ColormapId>(i));
  if (name == "coolwarm") return Colormap(ColormapId::cool_warm);  // matplotlib's spelling
  std::string allowed;
  for (const auto n : names) allowed += (allowed.empty() ? "" : ", ") + std::string(n);
  throw Error("unknown colour map '" + std::string(name) + "'; allowed: " + allowed);
}

std::span<const std::string_view> Colormap::names() { return table_names(); }

std::string_view Colormap::name() const { return colormap_tables::all[static_cast<int>(id_)].name; }

int Colormap::size() const { return table(id_).size; }

Rgb Colormap::rgb(double t) const {
  if (std::isnan(t)) return kNanColour;
  const auto& tab = table(id_);
  t = std::clamp(t, 0.0, 1.0);
  if (categorical()) {
    const int k = std::min(static_cast<int>(t * tab.size), tab.size - 1);
    return {tab.rgb[k][0], tab.rgb[k][1], tab.rgb[k][2]};
  }
  const double x = t * (tab.size - 1);
  const int k = std::min(static_cast<int>(x), tab.size - 2);
  const float f = static_cast<float>(x - k);
  const float* a = tab.rgb[k];
  const float* b = tab.rgb[k + 1];
  return {a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])};
}

Rgba8 Colormap::rgba8(double t) const { return to_rgba8(rgb(t)); }

Rgb Colormap::category(long long k) const {
  const auto& tab = table(id_);
  const long long m = ((k % tab.size) + tab.size) % tab.size;
  return {tab.rgb[m][0], tab.rgb[m][1], tab.rgb[m][2]};
}

std::vector<Rgba8> Colormap::to_texture(int n) const {
  if (n < 1) throw Error("colour-map texture size must be >= 1, got " + std::to_string(n));
  std::vector<Rgba8> out(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) out[i] = rgba8(n == 1 ? 0.5 : static_cast<double>(i) / (n - 1));
  return out;
}

Rgba8 to_rgba8(const Rgb& c) { return {to_byte(c.r), to_byte(c.g), to_byte(c.b), 255}; }

}  // namespace grainflow::render
