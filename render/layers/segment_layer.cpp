#include "render/layers/segment_layer.hpp"

#include <cmath>
#include <cstdint>

namespace grainflow::render {

void add_polyline(std::vector<Segment>& out, const std::vector<Eigen::Vector3f>& points, Rgb colour, float width_px,
                  float alpha, bool closed) {
  const std::size_t n = points.size();
  if (n < 2) return;
  const std::size_t count = closed ? n : n - 1;
  for (std::size_t i = 0; i < count; ++i) {
    const auto& a = points[i];
    const auto& b = points[(i + 1) % n];
    out.push_back({{a.x(), a.y(), a.z()}, {b.x(), b.y(), b.z()}, {colour.r, colour.g, colour.b, alpha}, width_px});
  }
}

void add_circle(std::vector<Segment>& out, Eigen::Vector2f centre, float radius, Rgb colour, float width_px,
                int pieces) {
  std::vector<Eigen::Vector3f> pts;
  pts.reserve(static_cast<std::size_t>(pieces));
  for (int i = 0; i < pieces; ++i) {
    const double a = 2 * M_PI * i / pieces;
    pts.emplace_back(centre.x() + radius * float(std::cos(a)), centre.y() + radius * float(std::sin(a)), 0.0f);
  }
  add_polyline(out, pts, colour, width_px, 1.0f, true);
}

void add_box_edges(std::vector<Segment>& out, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, Rgb colour,
                   float width_px) {
  auto corner = [&](int k) {
    return Eigen::Vector3f(float((k & 1) ? hi.x() : lo.x()), float((k & 2) ? hi.y() : lo.y()),
                           float((k & 4) ? hi.z() : lo.z()));
  };
  // The 12 edges join corners that differ in exactly one coordinate bit.
  for (int a = 0; a < 8; ++a)
    for (int bit : {1, 2, 4})
      if (!(a & bit)) {
        const auto p = corner(a), q = corner(a | bit);
        out.push_back({{p.x(), p.y(), p.z()}, {q.x(), q.y(), q.z()}, {colour.r, colour.g, colour.b, 1.0f}, width_px});
      }
}

SegmentLayer::SegmentLayer(const GlApi& gl)
    : gl_(gl), program_(gl, "segments.vert", "segments.frag"), vao_(gl), buffer_(gl) {}

void SegmentLayer::draw(const ViewTransform& view, int width, int height, const std::vector<Segment>& segments,
                        bool depth_test) {
  if (segments.empty()) return;
  vao_.bind();
  buffer_.upload(segments.data(), segments.size() * sizeof(Segment));
  const GLsizei stride = sizeof(Segment);
  auto attrib = [&](GLuint loc, GLint n, std::size_t offset_floats) {
    gl_.EnableVertexAttribArray(loc);
    gl_.VertexAttribPointer(loc, n, GL_FLOAT, GL_FALSE, stride,
                            reinterpret_cast<const void*>(offset_floats * sizeof(float)));
    gl_.VertexAttribDivisor(loc, 1);
  };
  attrib(0, 3, 0);
  attrib(1, 3, 3);
  attrib(2, 4, 6);
  attrib(3, 1, 10);
  program_.use();
  const Mat4 vp = view.view_proj();
  gl_.UniformMatrix4fv(program_.uniform("u_view_proj"), 1, GL_FALSE, vp.data());
  gl_.Uniform2f(program_.uniform("u_viewport"), float(width), float(height));
  gl_.Enable(GL_BLEND);
  gl_.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  if (depth_test) {
    gl_.Enable(GL_DEPTH_TEST);
    gl_.DepthMask(GL_FALSE);
  } else {
    gl_.Disable(GL_DEPTH_TEST);
  }
  gl_.DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, static_cast<GLsizei>(segments.size()));
  gl_.DepthMask(GL_TRUE);
  gl_.Disable(GL_BLEND);
}

}  // namespace grainflow::render
