// Particle layers: 2D anti-aliased disks and 3D lit sphere impostors with exact depth,
// coloured through a colour map. Point sprites are the fast path on llvmpipe (one vertex
// per particle); instanced quads take over when a particle is wider than the largest
// point size the driver allows.
#pragma once
#include <memory>
#include <array>
#include <optional>
#include <cstdint>
#include <span>
#include <vector>

#include "render/context/gl_context.hpp"
#include "render/context/shader_program.hpp"
#include "render/layers/camera.hpp"
#include "render/layers/colormap.hpp"
#include "render/layers/disk_splatter.hpp"
#include "render/layers/sphere_culling.hpp"
#include "render/layers/gl_buffer.hpp"

namespace grainflow::render {

struct ParticleDrawStyle {
  Colormap colormap{ColormapId::viridis};
  bool categorical = false;
  std::optional<Rgb> flat_colour;  // draw all particles in one colour (no attribute)
  // 3D spheres: the world-space box (lo x, y, z, hi x, y, z) outside which a sphere's surface
  // is cut away, so that a sphere and its periodic image each show their part inside the box.
  std::optional<std::array<float, 6>> clip_box;
};

// Texture coordinate of category k in a categorical map of n entries (k mod n, centred).
inline float category_coordinate(long long k, int n) {
  const long long m = ((k % n) + n) % n;
  return (static_cast<float>(m) + 0.5f) / static_cast<float>(n);
}

// How 2D disks reach the screen. Sprites: one point sprite (or quad) per disk, the GPU
// path. Splat: rasterised on the CPU (DiskSplatter) and drawn as one textured quad — far
// faster on a software rasteriser. Auto picks Splat on llvmpipe/softpipe for ≥ 5,000
// disks no wider than 32 px, Sprites otherwise.
enum class DiskMethod { Auto, Sprites, Splat };

// Whether hidden spheres are dropped on the CPU before drawing (SphereCuller). Auto: on
// software GL for ≥ 5,000 spheres, where every hidden fragment costs full ray casting.
enum class SphereCulling { Auto, On, Off };

class ParticleLayer {
public:
  explicit ParticleLayer(const GlApi& gl);

  SphereCulling sphere_culling = SphereCulling::Auto;
  // Spheres sent to GL by the last draw_spheres() (after culling).
  std::size_t last_spheres_drawn() const { return last_spheres_drawn_; }

  DiskMethod disk_method = DiskMethod::Auto;

  // pos_radius: 4 floats per particle; values: colour coordinate per particle, already
  // normalised to [0, 1] (NaN: no value; categories via category_coordinate()).
  // Empty values ⇒ flat colour (style.flat_colour or the map's mid colour).
  void draw_disks(const ViewTransform& view, int width, int height, std::span<const float> pos_radius,
                  std::span<const float> values, const ParticleDrawStyle& style);
  void draw_spheres(const ViewTransform& view, int width, int height, std::span<const float> pos_radius,
                    std::span<const float> values, const ParticleDrawStyle& style);

private:
  void draw_disks_splat(const ViewTransform& view, int width, int height, std::span<const float> pos_radius,
                        std::span<const float> values, const ParticleDrawStyle& style);
  void upload(std::span<const float> pos_radius, std::span<const float> values);
  void draw_uploaded(bool quads);
  static std::vector<Rgba8> colormap_texels(const ParticleDrawStyle& style);
  void bind_colormap(const ParticleDrawStyle& style);
  void set_colour_uniforms(const ShaderProgram& p, const ParticleDrawStyle& style, bool has_values);
  float max_radius(std::span<const float> pos_radius) const;

  const GlApi& gl_;
  ShaderProgram disk_points_, disk_quads_, sphere_points_, sphere_quads_;
  ShaderProgram composite_;
  bool software_gl_ = false;  // llvmpipe/softpipe: many small disks are splatted on the CPU
  GlVertexArray vao_;
  GlBuffer pos_buffer_, value_buffer_;
  GlTexture colormap_texture_;
  DiskSplatter splatter_;
  SphereCuller culler_;
  std::vector<float> culled_pos_, culled_values_;
  std::size_t last_spheres_drawn_ = 0;
  GlTexture splat_texture_;
  std::optional<ColormapId> uploaded_map_;
  bool uploaded_categorical_ = false;
  float max_point_size_ = 1;
  std::size_t count_ = 0;
};

}  // namespace grainflow::render
