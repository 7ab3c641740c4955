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
                         const Colormap& colormap, FieldFilter filter) {
  const auto& g = field.grid;
  if (g.nx < 1 || g.ny < 1 || field.values.size() != g.size()) return;
  const double lo = range.first, span = range.second - range.first;
  const double inv = span > 0 && std::isfinite(span) ? 1.0 / span : 0.0;
  texels_.resize(2 * g.size());
  for (std::size_t i = 0; i < g.size(); ++i) {
    const double v = field.values[i];
    const bool ok = (field.mask.empty() || field.mask[i]) && std::isfinite(v);
    // Clamped on the CPU too: a huge finite value must not become inf in 32-bit float.
    texels_[2 * i] = ok ? float(std::clamp(inv > 0 ? (v - lo) * inv : 0.5, -1.0, 2.0)) : 0.0f;
    texels_[2 * i + 1] = ok ? 1.0f : 0.0f;
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
