// Thick anti-aliased line segments with widths in pixels (core-profile GL has no wide
// lines): domain outlines, box edges, obstacle outlines, and later streamlines and arrows.
#pragma once
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
void add_box_edges(std::vector<Segment>& out, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, Rgb colour,
                   float width_px);

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
