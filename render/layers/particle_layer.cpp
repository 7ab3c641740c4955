#include "render/layers/particle_layer.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

namespace grainflow::render {

ParticleLayer::ParticleLayer(const GlApi& gl)
    : gl_(gl),
      disk_points_(gl, "disks.vert", "disks.frag"),
      disk_quads_(gl, "disks.vert", "disks.frag", "#define QUADS\n"),
      sphere_points_(gl, "spheres.vert", "spheres.frag"),
      sphere_quads_(gl, "spheres.vert", "spheres.frag", "#define QUADS\n"),
      composite_(gl, "fullscreen.vert", "composite.frag"),
      vao_(gl),
      pos_buffer_(gl),
      value_buffer_(gl),
      colormap_texture_(gl),
      splat_texture_(gl) {
  const auto* renderer = reinterpret_cast<const char*>(gl_.GetString(GL_RENDERER));
  const std::string name = renderer ? renderer : "";
  software_gl_ = name.find("llvmpipe") != std::string::npos || name.find("softpipe") != std::string::npos ||
                 name.find("swrast") != std::string::npos;
  GLfloat range[2] = {1, 1};
  gl_.GetFloatv(GL_POINT_SIZE_RANGE, range);
  max_point_size_ = range[1];
}

void ParticleLayer::upload(std::span<const float> pos_radius, std::span<const float> values) {
  count_ = pos_radius.size() / 4;
  vao_.bind();
  pos_buffer_.upload(pos_radius.data(), pos_radius.size_bytes());
  gl_.EnableVertexAttribArray(0);
  gl_.VertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 4 * sizeof(float), nullptr);
  gl_.VertexAttribDivisor(0, 1);
  // Attribute 1 always comes from a buffer, NaN-filled when there are no values, so the
  // shaders have one code path.
  if (values.size() == count_) {
    value_buffer_.upload(values.data(), values.size_bytes());
  } else {
    const std::vector<float> none(count_, std::nanf(""));
    value_buffer_.upload(none.data(), none.size() * sizeof(float));
  }
  gl_.EnableVertexAttribArray(1);
  gl_.VertexAttribPointer(1, 1, GL_FLOAT, GL_FALSE, sizeof(float), nullptr);
  gl_.VertexAttribDivisor(1, 1);
}

// The table both the GL texture and the CPU splatter sample: 256 entries of a continuous
// map, or one entry per category.
std::vector<Rgba8> ParticleLayer::colormap_texels(const ParticleDrawStyle& style) {
  if (!style.categorical) return style.colormap.to_texture(256);
  std::vector<Rgba8> texels;
  for (int k = 0; k < style.colormap.size(); ++k) texels.push_back(to_rgba8(style.colormap.category(k)));
  return texels;
}

void ParticleLayer::bind_colormap(const ParticleDrawStyle& style) {
  gl_.ActiveTexture(GL_TEXTURE0);
  gl_.BindTexture(GL_TEXTURE_2D, colormap_texture_.id());
  if (uploaded_map_ == style.colormap.id() && uploaded_categorical_ == style.categorical) return;
  const std::vector<Rgba8> texels = colormap_texels(style);
  gl_.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, static_cast<GLsizei>(texels.size()), 1, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                 texels.data());
  const GLint filter = style.categorical ? GL_NEAREST : GL_LINEAR;
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  uploaded_map_ = style.colormap.id();
  uploaded_categorical_ = style.categorical;
}

void ParticleLayer::set_colour_uniforms(const ShaderProgram& p, const ParticleDrawStyle& style, bool has_values) {
  gl_.Uniform1i(p.uniform("u_colormap"), 0);
  const Rgb nan = Colormap::kNanColour;
  gl_.Uniform3f(p.uniform("u_nan_colour"), nan.r, nan.g, nan.b);
  if (style.flat_colour) {
    gl_.Uniform4f(p.uniform("u_flat_colour"), style.flat_colour->r, style.flat_colour->g, style.flat_colour->b, 1);
  } else if (!has_values) {
    const Rgb mid = style.colormap.rgb(0.5);
    gl_.Uniform4f(p.uniform("u_flat_colour"), mid.r, mid.g, mid.b, 1);
  } else {
    gl_.Uniform4f(p.uniform("u_flat_colour"), 0, 0, 0, 0);
  }
}

float ParticleLayer::max_radius(std::span<const float> pos_radius) const {
  float r = 0;
  for (std::size_t i = 3; i < pos_radius.size(); i += 4) r = std::max(r, pos_radius[i]);
  return r;
}

void ParticleLayer::draw_disks(const ViewTransform& view, int width, int height, std::span<const float> pos_radius,
                               std::span<const float> values, const ParticleDrawStyle& style) {
  if (pos_radius.size() < 4) return;
  const float max_radius_px = max_radius(pos_radius) * view.pixels_per_unit;
  const std::size_t n = pos_radius.size() / 4;
  const bool splat = disk_method == DiskMethod::Splat ||
                     (disk_method == DiskMethod::Auto && software_gl_ && n >= 5000 && 2 * max_radius_px <= 32);
  if (splat) {
    draw_disks_splat(view, width, height, pos_radius, values, style);
    return;
  }
  upload(pos_radius, values);
  const bool quads = 2 * max_radius_px + 2 > max_point_size_;
  const ShaderProgram& p = quads ? disk_quads_ : disk_points_;
  p.use();
  bind_colormap(style);
  set_colour_uniforms(p, style, values.size() == count_);
  const Mat4 vp = view.view_proj();
  gl_.UniformMatrix4fv(p.uniform("u_view_proj"), 1, GL_FALSE, vp.data());
  gl_.Uniform1f(p.uniform("u_pixels_per_unit"), view.pixels_per_unit);
  gl_.Uniform2f(p.uniform("u_viewport"), float(width), float(height));
  gl_.Enable(GL_BLEND);
  gl_.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  gl_.Disable(GL_DEPTH_TEST);
  draw_uploaded(quads);
  gl_.Disable(GL_BLEND);
}

void ParticleLayer::draw_disks_splat(const ViewTransform& view, int width, int height,
                                     std::span<const float> pos_radius, std::span<const float> values,
                                     const ParticleDrawStyle& style) {
  const std::vector<Rgba8> texels = colormap_texels(style);
  const Rgba8 flat = to_rgba8(style.flat_colour ? *style.flat_colour : style.colormap.rgb(0.5));
  splatter_.splat(view, width, height, pos_radius, values, texels, style.categorical, flat,
                  to_rgba8(Colormap::kNanColour));
  gl_.ActiveTexture(GL_TEXTURE1);
  gl_.BindTexture(GL_TEXTURE_2D, splat_texture_.id());
  gl_.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  gl_.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, splatter_.pixels().data());
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  composite_.use();
  gl_.Uniform1i(composite_.uniform("u_image"), 1);
  GLint viewport[4] = {0, 0, width, height};  // a panel's viewport starts off the origin
  gl_.GetIntegerv(GL_VIEWPORT, viewport);
  gl_.Uniform2f(composite_.uniform("u_origin"), float(viewport[0]), float(viewport[1]));
  gl_.Enable(GL_BLEND);
  gl_.BlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  gl_.Disable(GL_DEPTH_TEST);
  vao_.bind();
  gl_.DrawArrays(GL_TRIANGLES, 0, 3);
  gl_.Disable(GL_BLEND);
  gl_.ActiveTexture(GL_TEXTURE0);
}

void ParticleLayer::draw_spheres(const ViewTransform& view, int width, int height, std::span<const float> pos_radius,
                                 std::span<const float> values, const ParticleDrawStyle& style) {
  if (pos_radius.size() < 4) return;
  const std::size_t n = pos_radius.size() / 4;
  if (sphere_culling == SphereCulling::On || (sphere_culling == SphereCulling::Auto && software_gl_ && n >= 5000)) {
    // Draw only the spheres that can show a pixel (same picture, far fewer fragments).
    const auto& keep = culler_.visible(view, width, height, pos_radius);
    culled_pos_.resize(keep.size() * 4);
    culled_values_.resize(values.size() == n ? keep.size() : 0);
    for (std::size_t k = 0; k < keep.size(); ++k) {
      std::copy_n(&pos_radius[4 * std::size_t(keep[k])], 4, &culled_pos_[4 * k]);
      if (!culled_values_.empty()) culled_values_[k] = values[keep[k]];
    }
    last_spheres_drawn_ = keep.size();
    pos_radius = culled_pos_;
    values = culled_values_;
    if (pos_radius.empty()) return;
  } else {
    last_spheres_drawn_ = n;
  }
  upload(pos_radius, values);
  // Largest sprite: the nearest sphere under perspective is bounded by the fit's scale
  // times a generous factor; go to quads when that could exceed the point-size limit.
  const bool quads = 2.5f * max_radius(pos_radius) * view.pixels_per_unit * 3.0f + 2 > max_point_size_;
  const ShaderProgram& p = quads ? sphere_quads_ : sphere_points_;
  p.use();
  bind_colormap(style);
  set_colour_uniforms(p, style, values.size() == count_);
  const Mat4 inv_proj = view.proj.inverse();
  gl_.UniformMatrix4fv(p.uniform("u_view"), 1, GL_FALSE, view.view.data());
  gl_.UniformMatrix4fv(p.uniform("u_proj"), 1, GL_FALSE, view.proj.data());
  gl_.UniformMatrix4fv(p.uniform("u_inv_proj"), 1, GL_FALSE, inv_proj.data());
  const Mat4 inv_view = view.view.inverse();
  gl_.UniformMatrix4fv(p.uniform("u_inv_view"), 1, GL_FALSE, inv_view.data());
  constexpr float kFar = 3e38f;  // no cut along an axis
  const std::array<float, 6> box = style.clip_box.value_or(std::array<float, 6>{-kFar, -kFar, -kFar, kFar, kFar, kFar});
  gl_.Uniform3f(p.uniform("u_clip_lo"), box[0], box[1], box[2]);
  gl_.Uniform3f(p.uniform("u_clip_hi"), box[3], box[4], box[5]);
  gl_.Uniform2f(p.uniform("u_viewport"), float(width), float(height));
  // The ray of a pixel comes from gl_FragCoord, which counts from the window's corner.
  GLint vp[4] = {0, 0, 0, 0};
  gl_.GetIntegerv(GL_VIEWPORT, vp);
  gl_.Uniform2f(p.uniform("u_viewport_origin"), float(vp[0]), float(vp[1]));
  gl_.Enable(GL_DEPTH_TEST);
  gl_.DepthFunc(GL_LESS);
  gl_.DepthMask(GL_TRUE);
  gl_.Disable(GL_BLEND);
  draw_uploaded(quads);
}

void ParticleLayer::draw_uploaded(bool quads) {
  vao_.bind();
  if (quads) {
    gl_.DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(count_));
  } else {
    gl_.Enable(GL_PROGRAM_POINT_SIZE);
    // Per-instance attributes with divisor 1 would not advance for GL_POINTS drawn as
    // vertices, so the point path draws one instance of `count_` points instead.
    gl_.VertexAttribDivisor(0, 0);
    gl_.VertexAttribDivisor(1, 0);
    gl_.DrawArrays(GL_POINTS, 0, static_cast<GLsizei>(count_));
  }
}

}  // namespace grainflow::render
