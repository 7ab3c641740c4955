#include "render/layers/segment_layer.hpp"

#include <algorithm>
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

void add_box(std::vector<Segment>& out, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
             const std::array<BoxFace, 6>& faces, const Eigen::Vector3d& eye, Rgb colour, float width_px) {
  auto corner = [&](int k) {
    return Eigen::Vector3f(float((k & 1) ? hi.x() : lo.x()), float((k & 2) ? hi.y() : lo.y()),
                           float((k & 4) ? hi.z() : lo.z()));
  };
  auto is_wall = [&](int axis, bool high) { return faces[std::size_t(2 * axis + (high ? 1 : 0))] == BoxFace::wall; };
  auto push = [&](const Eigen::Vector3f& p, const Eigen::Vector3f& q, float alpha, float w) {
    out.push_back({{p.x(), p.y(), p.z()}, {q.x(), q.y(), q.z()}, {colour.r, colour.g, colour.b, alpha}, w});
  };
  // The 12 edges join corners that differ in exactly one coordinate bit; an edge along
  // axis a borders the faces of the other two axes on its corner's sides.
  constexpr int kDashes = 12;  // dash + gap pairs along a periodic edge
  for (int a = 0; a < 8; ++a)
    for (int axis = 0; axis < 3; ++axis) {
      const int bit = 1 << axis;
      if (a & bit) continue;
      const auto p = corner(a), q = corner(a | bit);
      bool wall = false;
      for (int other = 0; other < 3; ++other)
        if (other != axis && is_wall(other, (a >> other) & 1)) wall = true;
      if (wall) {
        push(p, q, 1.0f, width_px);
        continue;
      }
      for (int k = 0; k < kDashes; ++k) {
        const float t0 = float(k) / kDashes, t1 = (float(k) + 0.55f) / kDashes;
        push(p + t0 * (q - p), p + t1 * (q - p), 0.6f, std::max(1.0f, 0.6f * width_px));
      }
    }
  // Hatching of the walls seen from inside: diagonals at 45° in the face's own units,
  // spaced a sixteenth of the face's longer side.
  for (int f = 0; f < 6; ++f) {
    if (faces[std::size_t(f)] != BoxFace::wall) continue;
    const int axis = f / 2;
    const bool high = f % 2 == 1;
    const double plane = high ? hi[axis] : lo[axis];
    // The inside of the face is towards the box centre: seen from inside when the eye
    // is on that side of the face's plane.
    const bool from_inside = high ? eye[axis] < plane : eye[axis] > plane;
    if (!from_inside) continue;
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    const double lu = hi[u] - lo[u], lv = hi[v] - lo[v];
    const double step = std::max(lu, lv) / 16.0;
    if (!(step > 0)) continue;
    // Lines u − lo_u + (v − lo_v) = c for c in (0, lu + lv), clipped to the face.
    for (double c = step; c < lu + lv; c += step) {
      const double u0 = std::min(c, lu), v0 = c - u0;   // start on the v = lo edge or the u = hi edge
      const double v1 = std::min(c, lv), u1 = c - v1;   // end on the u = lo edge or the v = hi edge
      Eigen::Vector3f p, q;
      p[axis] = q[axis] = float(plane);
      p[u] = float(lo[u] + u0), p[v] = float(lo[v] + v0);
      q[u] = float(lo[u] + u1), q[v] = float(lo[v] + v1);
      push(p, q, 0.3f, std::max(1.0f, 0.5f * width_px));
    }
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
