#include "render/layers/sphere_culling.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace grainflow::render {
namespace {
constexpr int kTile = 1;  // a per-pixel buffer: spheres are often only ~10 px wide
}

const std::vector<std::uint32_t>& SphereCuller::visible(const ViewTransform& view, int width, int height,
                                                        std::span<const float> pos_radius) {
  const std::size_t n = pos_radius.size() / 4;
  const bool ortho = view.proj(3, 3) > 0.5f;
  const float f = view.proj(1, 1) * 0.5f * float(height);  // pixels per unit at unit depth
  const Mat4 vp = view.view_proj();
  items_.clear();
  items_.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float* p = &pos_radius[4 * i];
    const Eigen::Vector4f c = view.view * Eigen::Vector4f(p[0], p[1], p[2], 1.0f);
    items_.push_back({-c.z() - p[3], std::uint32_t(i)});
  }
  std::sort(items_.begin(), items_.end(), [](const Item& a, const Item& b) {
    return a.near_depth < b.near_depth || (a.near_depth == b.near_depth && a.index < b.index);
  });

  const int tx = (width + kTile - 1) / kTile, ty = (height + kTile - 1) / kTile;
  tiles_.assign(std::size_t(tx) * ty, std::numeric_limits<float>::infinity());
  visible_.clear();
  for (const Item& it : items_) {
    const float* p = &pos_radius[4 * it.index];
    const float r = p[3];
    const Eigen::Vector4f v = view.view * Eigen::Vector4f(p[0], p[1], p[2], 1.0f);
    const Eigen::Vector4f clip = vp * Eigen::Vector4f(p[0], p[1], p[2], 1.0f);
    const float depth = -v.z();  // centre, in front of the eye
    if (!ortho && depth - r <= 0) {  // reaches behind the eye: never cull, never occlude
      visible_.push_back(it.index);
      continue;
    }
    const float cx = (clip.x() / clip.w() * 0.5f + 0.5f) * float(width);
    const float cy = (clip.y() / clip.w() * 0.5f + 0.5f) * float(height);
    // Outer bound of the silhouette (as the sprite shader) and an inner bound: the outline
    // of a sphere at distance D has radius ≥ f·R/D on the image plane.
    float outer, inner;
    if (ortho) {
      outer = inner = r * f;
    } else {
      outer = 1.06f * f * r / std::sqrt(std::max(depth * depth - r * r, 1e-12f));
      inner = 0.9f * f * r / v.head<3>().norm();  // 10 % margin: the outline is centred slightly off the projected centre
    }
    outer += 1.0f;  // anti-aliasing margin
    // The candidate shows unless every pixel its outline may touch is already covered by
    // a nearer sphere.
    const int x0 = std::max(0, int(std::floor(cx - outer))), x1 = std::min(tx - 1, int(std::floor(cx + outer)));
    const int y0 = std::max(0, int(std::floor(cy - outer))), y1 = std::min(ty - 1, int(std::floor(cy + outer)));
    if (x0 > x1 || y0 > y1) continue;  // off screen
    const float reach = (outer + 0.71f) * (outer + 0.71f);  // pixel squares the disk touches
    bool shows = false;
    for (int y = y0; y <= y1 && !shows; ++y) {
      const float dy = float(y) + 0.5f - cy;
      const float* row = &tiles_[std::size_t(y) * tx];
      for (int x = x0; x <= x1; ++x) {
        const float dx = float(x) + 0.5f - cx;
        if (dx * dx + dy * dy <= reach && row[x] > it.near_depth) {
          shows = true;
          break;
        }
      }
    }
    if (!shows) continue;
    visible_.push_back(it.index);
    // As an occluder: pixels whose whole square lies inside the inner outline are covered
    // by the front of this sphere, at a depth no larger than its centre's.
    const float in = inner - 0.71f;
    if (in <= 0) continue;
    const int ox0 = std::max(0, int(std::ceil(cx - in))), ox1 = std::min(tx - 1, int(std::floor(cx + in)));
    const int oy0 = std::max(0, int(std::ceil(cy - in))), oy1 = std::min(ty - 1, int(std::floor(cy + in)));
    const float in2 = in * in;
    for (int y = oy0; y <= oy1; ++y) {
      const float dy = float(y) + 0.5f - cy;
      float* row = &tiles_[std::size_t(y) * tx];
      for (int x = ox0; x <= ox1; ++x) {
        const float dx = float(x) + 0.5f - cx;
        if (dx * dx + dy * dy <= in2) row[x] = std::min(row[x], depth);
      }
    }
  }
  return visible_;
}

}  // namespace grainflow::render
