// Colour maps for particles and field maps: perceptually uniform viridis (default),
// inferno, magma, the rainbow-like turbo, Moreland's diverging cool-warm for signed values
// and the categorical tab10 for species (SPEC §3 "Layers").
#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

namespace grainflow::render {

enum class ColormapId { viridis, inferno, magma, turbo, cool_warm, tab10 };

struct Rgb {
  float r = 0, g = 0, b = 0;
};

struct Rgba8 {
  std::uint8_t r = 0, g = 0, b = 0, a = 255;
};
static_assert(sizeof(Rgba8) == 4, "to_texture() hands the vector's data() to GL as RGBA8");

class Colormap {
public:
  // Colour of NaN values (and of masked bins when a layer wants one): a neutral mid grey,
  // outside viridis/inferno/magma and darker than cool-warm's light grey centre (0.865).
  static constexpr Rgb kNanColour{0.5f, 0.5f, 0.5f};

  explicit Colormap(ColormapId id = ColormapId::viridis);

  // "viridis", "inferno", "magma", "turbo", "cool-warm" (also "coolwarm"), "tab10".
  // Anything else throws grainflow::Error listing the allowed names.
  static Colormap by_name(std::string_view name);
  // The canonical names, in ColormapId order.
  static std::span<const std::string_view> names();

  ColormapId id() const { return id_; }
  std::string_view name() const;
  // Categorical maps (tab10) are not interpolated: rgb(t) picks the entry floor(t·size).
  bool categorical() const { return id_ == ColormapId::tab10; }
  int size() const;

  // t in [0, 1]; values outside are clamped, NaN gives kNanColour. Continuous maps
  // interpolate linearly between the table entries, entry k sitting at t = k / (size − 1).
  Rgb rgb(double t) const;
  Rgba8 rgba8(double t) const;
  // Colour of category k (e.g. a particle type): entry k mod size, for any integer k.
  Rgb category(long long k) const;
  // n ≥ 1 samples at t = i / (n − 1) (t = 0.5 when n == 1), alpha 255, for a GL
  // RGBA8 1D texture: upload with glTexImage1D(..., n, ..., GL_RGBA, GL_UNSIGNED_BYTE, data()).
  std::vector<Rgba8> to_texture(int n = 256) const;

private:
  ColormapId id_;
};

Rgba8 to_rgba8(const Rgb& c);

}  // namespace grainflow::render
