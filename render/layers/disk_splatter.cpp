#include "render/layers/disk_splatter.hpp"

#include <algorithm>
#include <cmath>

namespace grainflow::render {
namespace {

// GL_LINEAR sampling of a 1D table at t ∈ [0, 1], as the sprite shader's texture() does.
Rgba8 sample_linear(const std::vector<Rgba8>& texels, float t) {
  const float n = float(texels.size());
  const float f = std::clamp(std::clamp(t, 0.0f, 1.0f) * n - 0.5f, 0.0f, n - 1.0f);
  const std::size_t a = std::size_t(f), b = std::min(a + 1, texels.size() - 1);
  const float w = f - float(a);
  auto mix = [w](std::uint8_t x, std::uint8_t y) { return std::uint8_t(std::lround(x + (y - x) * w)); };
  return {mix(texels[a].r, texels[b].r), mix(texels[a].g, texels[b].g), mix(texels[a].b, texels[b].b), 255};
}

float smoothstep(float e0, float e1, float x) {
  const float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3 - 2 * t);
}

}  // namespace

void DiskSplatter::splat(const ViewTransform& view, int width, int height, std::span<const float> pos_radius,
                         std::span<const float> values, const std::vector<Rgba8>& texels, bool categorical,
                         Rgba8 flat, Rgba8 nan_colour) {
  pixels_.assign(std::size_t(width) * height * 4, 0);
  const std::size_t n = pos_radius.size() / 4;
  const bool has_values = values.size() == n;
  const Mat4 vp = view.view_proj();
  // For the orthographic 2D view, window x = a·x + b (same for y).
  const float ax = vp(0, 0) * 0.5f * width, bx = (vp(0, 3) * 0.5f + 0.5f) * width;
  const float ay = vp(1, 1) * 0.5f * height, by = (vp(1, 3) * 0.5f + 0.5f) * height;
  for (std::size_t i = 0; i < n; ++i) {
    const float* d = &pos_radius[4 * i];
    const float cx = ax * d[0] + bx, cy = ay * d[1] + by, r = d[3] * view.pixels_per_unit;
    const int x0 = std::max(0, int(std::floor(cx - r - 0.5f))), x1 = std::min(width - 1, int(std::ceil(cx + r + 0.5f)));
    const int y0 = std::max(0, int(std::floor(cy - r - 0.5f))), y1 = std::min(height - 1, int(std::ceil(cy + r + 0.5f)));
    if (x0 > x1 || y0 > y1) continue;
    Rgba8 c = flat;
    if (has_values) {
      const float v = values[i];
      if (std::isnan(v)) c = nan_colour;
      else if (categorical) c = texels[std::min(std::size_t(std::max(v, 0.0f) * texels.size()), texels.size() - 1)];
      else c = sample_linear(texels, v);
    }
    const bool rimmed = r > 3.0f;
    const float rim_px = std::max(0.6f, 0.12f * r);
    for (int y = y0; y <= y1; ++y) {
      const float dy = float(y) + 0.5f - cy;
      std::uint8_t* row = pixels_.data() + std::size_t(y) * width * 4;
      for (int x = x0; x <= x1; ++x) {
        const float dx = float(x) + 0.5f - cx;
        const float dist = std::sqrt(dx * dx + dy * dy);
        const float coverage = std::clamp(r - dist + 0.5f, 0.0f, 1.0f);
        if (coverage <= 0.0f) continue;
        const float shade = rimmed ? 1.0f - 0.45f * smoothstep(r - rim_px - 0.5f, r - rim_px + 0.5f, dist) : 1.0f;
        std::uint8_t* p = row + 4 * x;
        // Premultiplied "over", in particle order like the sprite path's blending.
        const float keep = 1.0f - coverage, k = coverage * shade;
        // Values are ≥ 0, so +0.5 and truncation round to nearest (lround is a libm call).
        p[0] = std::uint8_t(c.r * k + p[0] * keep + 0.5f);
        p[1] = std::uint8_t(c.g * k + p[1] * keep + 0.5f);
        p[2] = std::uint8_t(c.b * k + p[2] * keep + 0.5f);
        p[3] = std::uint8_t(255.0f * coverage + p[3] * keep + 0.5f);
      }
    }
  }
}

}  // namespace grainflow::render
