// Thick anti-aliased line segments with widths in pixels (core-profile GL has no wide
// lines): domain outlines, box edges, obstacle outlines, and later streamlines and arrows.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "render/context/shader_program.hpp"
#include "render/layers/camera.hpp"
#include "render/layers/colormap.hpp"
#include "render/layers/gl_buffer.hpp"

namespace grainflow::render {

struct Segment {
  float p0[3];
  float p1[3];
  float rgba[4];
  float width_px;
};
static_assert(sizeof(Segment) == 11 * sizeof(float));

// Appends helpers build common shapes into a segment list.
void add_polyline(std::vector<Segment>& out, const std::vector<Eigen::Vector3f>& points, Rgb colour, float width_px,
                  float alpha = 1.0f, bool closed = false);
void add_circle(std::vector<Segment>& out, Eigen::Vector2f centre, float radius, Rgb colour, float width_px,
                int pieces = 96);
// What a face of a 3D box is, in the order x lo, x hi, y lo, y hi, z lo, z hi.
enum class BoxFace : std::uint8_t { wall, periodic, open };
// The box [lo, hi] drawn so that its kinds of faces read apart: an edge of a wall is solid
// and `width_px` wide; an edge between periodic or open faces only is dashed, thin and
// faint; a wall seen from inside (its inner side towards `eye`, so behind the particles)
// is hatched with faint diagonals. A wall seen from outside is not hatched: it would lie
// over the particles.
void add_box(std::vector<Segment>& out, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
             const std::array<BoxFace, 6>& faces, const Eigen::Vector3d& eye, Rgb colour, float width_px);

class SegmentLayer {
public:
  explicit SegmentLayer(const GlApi& gl);
  // depth_test: true for 3D scenes (edges hidden behind spheres).
  void draw(const ViewTransform& view, int width, int height, const std::vector<Segment>& segments,
            bool depth_test = false);

private:
  const GlApi& gl_;
  ShaderProgram program_;
  GlVertexArray vao_;
  GlBuffer buffer_;
};

}  // namespace grainflow::render
