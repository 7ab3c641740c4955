#include "render/layers/field_map_layer.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "engine/core/error.hpp"

namespace grainflow::render {

namespace {
std::pair<double, double> widen_if_constant(double lo, double hi) {
  if (hi > lo) return {lo, hi};
  const double half = lo != 0.0 ? 0.05 * std::abs(lo) : 0.5;
  return {lo - half, lo + half};
}

double percentile_of_sorted(const std::vector<double>& v, double p) {
  const double pos = p / 100.0 * double(v.size() - 1);
  const auto i = static_cast<std::size_t>(std::floor(pos));
  if (i + 1 >= v.size()) return v.back();
  const double f = pos - double(i);
  return v[i] + f * (v[i + 1] - v[i]);
}
}  // namespace

namespace {
std::pair<double, double> resolve_one_sided(const std::vector<double>& values, const FieldRange& range);
}  // namespace

std::pair<double, double> resolve_range(const std::vector<double>& values, const FieldRange& range) {
  const auto r = resolve_one_sided(values, range);
  if (!range.symmetric || range.mode == FieldRange::Mode::fixed) return r;
  const double m = std::max(std::abs(r.first), std::abs(r.second));
  return m > 0 ? std::pair{-m, m} : std::pair{-1.0, 1.0};
}

namespace {
std::pair<double, double> resolve_one_sided(const std::vector<double>& values, const FieldRange& range) {
  switch (range.mode) {
    case FieldRange::Mode::fixed:
      if (!(std::isfinite(range.lo) && std::isfinite(range.hi) && range.lo < range.hi))
        throw Error("colour range [" + std::to_string(range.lo) + ", " + std::to_string(range.hi) +
                    "] is not allowed; allowed: finite lo < hi");
      return {range.lo, range.hi};
    case FieldRange::Mode::automatic: {
      double lo = INFINITY, hi = -INFINITY;
      for (double v : values)
        if (std::isfinite(v)) {
          lo = std::min(lo, v);
          hi = std::max(hi, v);
        }
      if (lo > hi) return {0.0, 1.0};
      return widen_if_constant(lo, hi);
    }
    case FieldRange::Mode::percentile: {
      if (!(range.lo_percent >= 0.0 && range.lo_percent < range.hi_percent && range.hi_percent <= 100.0))
        throw Error("percentile range [" + std::to_string(range.lo_percent) + ", " +
                    std::to_string(range.hi_percent) + "] is not allowed; allowed: 0 ≤ lo < hi ≤ 100");
      std::vector<double> finite;
      finite.reserve(values.size());
      for (double v : values)
        if (std::isfinite(v)) finite.push_back(v);
      if (finite.empty()) return {0.0, 1.0};
      std::sort(finite.begin(), finite.end());
      return widen_if_constant(percentile_of_sorted(finite, range.lo_percent),
                               percentile_of_sorted(finite, range.hi_percent));
    }
  }
  return {0.0, 1.0};
}
}  // namespace

std::pair<double, double> resolve_range(const core::ScalarField& field, const FieldRange& range) {
  std::vector<double> valid;
  valid.reserve(field.values.size());
  for (std::size_t i = 0; i < field.values.size(); ++i)
    if (field.mask.empty() || field.mask[i]) valid.push_back(field.values[i]);
  return resolve_range(valid, range);
}

void fill_bins_under_solids(const core::GridGeometry& g, std::vector<float>& values, std::vector<std::uint8_t>& valid,
                            std::span<const SolidCircle> solids) {
  if (solids.empty() || g.nx < 1 || g.ny < 1 || values.size() != g.size() || valid.size() != g.size()) return;
  // Bins whose square reaches into a circle: the nearest point of the square to the
  // centre lies inside it.
  const double dx = g.dx(), dy = g.dy();
  std::vector<std::size_t> pending;
  for (int iy = 0; iy < g.ny; ++iy)
    for (int ix = 0; ix < g.nx; ++ix) {
      const std::size_t b = g.index(ix, iy);
      if (valid[b]) continue;
      const double x0 = g.lo.x() + ix * dx, y0 = g.lo.y() + iy * dy;
      for (const SolidCircle& c : solids) {
        const double nx = std::clamp(c.centre.x(), x0, x0 + dx) - c.centre.x();
        const double ny = std::clamp(c.centre.y(), y0, y0 + dy) - c.centre.y();
        if (nx * nx + ny * ny < c.radius * c.radius) {
          pending.push_back(b);
          break;
        }
      }
    }
  std::vector<std::pair<std::size_t, float>> filled;
  while (!pending.empty()) {
    filled.clear();
    std::vector<std::size_t> left;
    for (std::size_t b : pending) {
      const int ix = int(b % std::size_t(g.nx)), iy = int(b / std::size_t(g.nx));
      double sum = 0;
      int n = 0;
      for (int jy = std::max(0, iy - 1); jy <= std::min(g.ny - 1, iy + 1); ++jy)
        for (int jx = std::max(0, ix - 1); jx <= std::min(g.nx - 1, ix + 1); ++jx) {
          const std::size_t k = g.index(jx, jy);
          if (valid[k]) sum += values[k], ++n;
        }
      if (n > 0) filled.emplace_back(b, float(sum / n));
      else left.push_back(b);
    }
    if (filled.empty()) break;  // the rest has no valid bin anywhere near: stays masked
    for (const auto& [b, v] : filled) values[b] = v, valid[b] = 1;
    pending = std::move(left);
  }
}

FieldMapLayer::FieldMapLayer(const GlApi& gl)
    : gl_(gl), program_(gl, "field_map.vert", "field_map.frag"), vao_(gl), field_texture_(gl), colormap_texture_(gl) {}

void FieldMapLayer::bind_colormap(const Colormap& colormap) {
  gl_.ActiveTexture(GL_TEXTURE1);
  gl_.BindTexture(GL_TEXTURE_2D, colormap_texture_.id());
  if (uploaded_map_ != colormap.id()) {
    const std::vector<Rgba8> table = colormap.to_texture(256);
    gl_.PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    gl_.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 256, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, table.data());
    const GLint filter = colormap.categorical() ? GL_NEAREST : GL_LINEAR;
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    uploaded_map_ = colormap.id();
  }
}

void FieldMapLayer::draw_texels(const ViewTransform& view, int nx, int ny, const Eigen::Vector2d& lo,
                                const Eigen::Vector2d& hi, bool bilinear) {
  gl_.ActiveTexture(GL_TEXTURE0);
  gl_.BindTexture(GL_TEXTURE_2D, field_texture_.id());
  gl_.PixelStorei(GL_UNPACK_ALIGNMENT, 4);
  gl_.TexImage2D(GL_TEXTURE_2D, 0, GL_RG32F, nx, ny, 0, GL_RG, GL_FLOAT, texels_.data());
  // The shader reads bins with texelFetch; filtering state only has to make the texture
  // complete (no mipmaps).
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  program_.use();
  gl_.Uniform1i(program_.uniform("u_field"), 0);
  gl_.Uniform1i(program_.uniform("u_colormap"), 1);
  gl_.Uniform1i(program_.uniform("u_bilinear"), bilinear ? 1 : 0);
  gl_.Uniform2f(program_.uniform("u_lo"), float(lo.x()), float(lo.y()));
  gl_.Uniform2f(program_.uniform("u_hi"), float(hi.x()), float(hi.y()));
  const Rgb nan = Colormap::kNanColour;
  gl_.Uniform3f(program_.uniform("u_nan_colour"), nan.r, nan.g, nan.b);
  const Mat4 vp = view.view_proj();
  gl_.UniformMatrix4fv(program_.uniform("u_view_proj"), 1, GL_FALSE, vp.data());
  gl_.Disable(GL_BLEND);
  gl_.Disable(GL_DEPTH_TEST);
  vao_.bind();
  gl_.DrawArrays(GL_TRIANGLE_STRIP, 0, 4);
  gl_.ActiveTexture(GL_TEXTURE0);
}

void FieldMapLayer::draw(const ViewTransform& view, const core::ScalarField& field, std::pair<double, double> range,
                         const Colormap& colormap, FieldFilter filter, std::span<const SolidCircle> solids) {
  const auto& g = field.grid;
  if (g.nx < 1 || g.ny < 1 || field.values.size() != g.size()) return;
  const double lo = range.first, span = range.second - range.first;
  const double inv = span > 0 && std::isfinite(span) ? 1.0 / span : 0.0;
  values_.resize(g.size());
  valid_.resize(g.size());
  for (std::size_t i = 0; i < g.size(); ++i) {
    const double v = field.values[i];
    const bool ok = (field.mask.empty() || field.mask[i]) && std::isfinite(v);
    // Clamped on the CPU too: a huge finite value must not become inf in 32-bit float.
    values_[i] = ok ? float(std::clamp(inv > 0 ? (v - lo) * inv : 0.5, -1.0, 2.0)) : 0.0f;
    valid_[i] = ok ? 1 : 0;
  }
  fill_bins_under_solids(g, values_, valid_, solids);
  texels_.resize(2 * g.size());
  for (std::size_t i = 0; i < g.size(); ++i) {
    texels_[2 * i] = values_[i];
    texels_[2 * i + 1] = valid_[i] ? 1.0f : 0.0f;
  }
  bind_colormap(colormap);
  draw_texels(view, g.nx, g.ny, g.lo, g.hi, filter == FieldFilter::bilinear);
}

void FieldMapLayer::draw_gradient(const ViewTransform& view, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
                                  const Colormap& colormap) {
  constexpr int n = 256;
  texels_.resize(2 * n);
  for (int i = 0; i < n; ++i) {
    texels_[2 * i] = float(i) / (n - 1);
    texels_[2 * i + 1] = 1.0f;
  }
  bind_colormap(colormap);
  draw_texels(view, 1, n, lo, hi, !colormap.categorical());
}

}  // namespace grainflow::render
