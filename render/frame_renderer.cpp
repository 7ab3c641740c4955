#include "render/frame_renderer.hpp"

#include "render/panel_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace grainflow::render {

std::pair<double, double> finite_range(std::span<const float> values) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (float v : values)
    if (std::isfinite(v)) {
      lo = std::min(lo, double(v));
      hi = std::max(hi, double(v));
    }
  if (lo > hi) return {0.0, 1.0};
  return {lo, hi};
}

namespace {

// Particles with their images across the periodic faces of the box [lo, hi] (x and y in
// 2D, x, y and z in 3D): a particle reaching past a face is repeated one period away,
// diagonally too at an edge or a corner (up to 3 images in 2D, 7 in 3D).
void add_periodic_images(const Snapshot& s, std::span<const float> values, std::vector<float>& pos,
                         std::vector<float>& vals) {
  pos.assign(s.pos_radius.begin(), s.pos_radius.end());
  vals.assign(values.begin(), values.end());
  const int dims = s.dim == 3 ? 3 : 2;
  const float lo[3] = {float(s.lo.x()), float(s.lo.y()), float(s.lo.z())},
              hi[3] = {float(s.hi.x()), float(s.hi.y()), float(s.hi.z())};
  for (std::size_t i = 0; i < s.size(); ++i) {
    const float* d = &s.pos_radius[4 * i];
    float shift[3][2] = {};  // per axis: none and up to one image
    int count[3] = {1, 1, 1};
    for (int a = 0; a < dims; ++a) {
      if (!s.periodic[std::size_t(a)]) continue;
      const float len = hi[a] - lo[a];
      if (d[a] - d[3] < lo[a]) shift[a][count[a]++] = len;
      else if (d[a] + d[3] > hi[a]) shift[a][count[a]++] = -len;
    }
    for (int ax = 0; ax < count[0]; ++ax)
      for (int ay = 0; ay < count[1]; ++ay)
        for (int az = 0; az < count[2]; ++az) {
          if (ax == 0 && ay == 0 && az == 0) continue;
          pos.insert(pos.end(), {d[0] + shift[0][ax], d[1] + shift[1][ay], d[2] + shift[2][az], d[3]});
          if (!values.empty()) vals.push_back(values[i]);
        }
  }
}

// Restricts drawing to the box's pixels along its periodic axes (within any scissor box
// already set, e.g. a panel's) and restores the previous state when it goes.
class PeriodicClip {
public:
  PeriodicClip(const GlApi& gl, const Snapshot& s, const ViewTransform& view, int width, int height) : gl_(gl) {
    was_enabled_ = gl.IsEnabled(GL_SCISSOR_TEST) == GL_TRUE;
    gl.GetIntegerv(GL_SCISSOR_BOX, old_box_);
    GLint vp[4] = {0, 0, width, height};
    gl.GetIntegerv(GL_VIEWPORT, vp);
    auto pixel = [&](double x, double y) {  // GL window pixels, origin bottom-left
      const Eigen::Vector2d c = view.ndc(x, y);
      return Eigen::Vector2d(vp[0] + (c.x() + 1) * 0.5 * vp[2], vp[1] + (c.y() + 1) * 0.5 * vp[3]);
    };
    const Eigen::Vector2d a = pixel(s.lo.x(), s.lo.y()), b = pixel(s.hi.x(), s.hi.y());
    int x0 = vp[0], x1 = vp[0] + vp[2], y0 = vp[1], y1 = vp[1] + vp[3];
    if (s.periodic[0]) {
      x0 = int(std::lround(std::min(a.x(), b.x())));
      x1 = int(std::lround(std::max(a.x(), b.x())));
    }
    if (s.periodic[1]) {
      y0 = int(std::lround(std::min(a.y(), b.y())));
      y1 = int(std::lround(std::max(a.y(), b.y())));
    }
    if (was_enabled_) {
      x0 = std::max(x0, old_box_[0]);
      y0 = std::max(y0, old_box_[1]);
      x1 = std::min(x1, old_box_[0] + old_box_[2]);
      y1 = std::min(y1, old_box_[1] + old_box_[3]);
    }
    gl.Enable(GL_SCISSOR_TEST);
    gl.Scissor(x0, y0, std::max(0, x1 - x0), std::max(0, y1 - y0));
  }
  ~PeriodicClip() {
    gl_.Scissor(old_box_[0], old_box_[1], old_box_[2], old_box_[3]);
    if (!was_enabled_) gl_.Disable(GL_SCISSOR_TEST);
  }
  PeriodicClip(const PeriodicClip&) = delete;
  PeriodicClip& operator=(const PeriodicClip&) = delete;

private:
  const GlApi& gl_;
  bool was_enabled_ = false;
  GLint old_box_[4] = {0, 0, 0, 0};
};

}  // namespace

FrameRenderer::FrameRenderer(GlContext& context, int width, int height, int msaa_samples)
    : ctx_(context), fb_(context.gl(), width, height, msaa_samples), particles_(context.gl()), segments_(context.gl()) {}

FrameRenderer::~FrameRenderer() = default;

ViewTransform FrameRenderer::scene_view(const Snapshot& s, const FrameStyle& style, int w, int h) const {
  return s.dim == 2 ? fit_2d(s.lo.head<2>(), s.hi.head<2>(), style.camera, w, h) : fit_3d(s.lo, s.hi, style.camera, w, h);
}

const Image& FrameRenderer::render(const Snapshot& s, const FrameStyle& style) {
  const GlApi& gl = ctx_.gl();
  const int w = fb_.width(), h = fb_.height();
  fb_.bind();
  gl.ClearColor(style.background.r, style.background.g, style.background.b, 1.0f);
  gl.ClearDepth(1.0);
  gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  const ViewTransform view = scene_view(s, style, w, h);
  draw_particles(s, style, view, w, h);
  draw_geometry(s, style, view, w, h);
  fb_.read(image_);
  return image_;
}

const Image& FrameRenderer::render(const Snapshot& s, const FrameStyle& style, const FrameLayout& layout) {
  const GlApi& gl = ctx_.gl();
  if (!panels_) panels_ = std::make_unique<PanelRenderer>(gl);
  fb_.bind();
  gl.ClearColor(style.background.r, style.background.g, style.background.b, 1.0f);
  gl.ClearDepth(1.0);
  gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  panels_->draw(*this, s, style, layout, fb_.width(), fb_.height());
  gl.Viewport(0, 0, fb_.width(), fb_.height());
  fb_.read(image_);
  return image_;
}

void FrameRenderer::draw_particles(const Snapshot& s, const FrameStyle& style, const ViewTransform& view, int w,
                                   int h) {
  // Colour coordinates in [0, 1]; a constant attribute sits at the map's centre.
  values_.clear();
  ParticleDrawStyle pstyle{style.colormap, s.attribute_categorical, std::nullopt, std::nullopt};
  if (s.attribute.size() == s.size() && s.size() > 0) {
    values_.resize(s.size());
    if (s.attribute_categorical) {
      const int n = style.colormap.size();
      for (std::size_t i = 0; i < s.size(); ++i)
        values_[i] = std::isfinite(s.attribute[i]) ? category_coordinate(std::llround(s.attribute[i]), n)
                                                   : std::nanf("");
    } else {
      const auto [lo, hi] = style.range ? *style.range : finite_range(s.attribute);
      const double span = hi - lo;
      for (std::size_t i = 0; i < s.size(); ++i) {
        const float v = s.attribute[i];
        values_[i] = !std::isfinite(v) ? std::nanf("") : span > 0 ? float((v - lo) / span) : 0.5f;
      }
    }
  }

  if (s.dim == 2 && (s.periodic[0] || s.periodic[1])) {
    add_periodic_images(s, values_, wrapped_pos_, wrapped_values_);
    const PeriodicClip clip(ctx_.gl(), s, view, w, h);
    particles_.draw_disks(view, w, h, wrapped_pos_, wrapped_values_, pstyle);
  } else if (s.dim == 2) {
    particles_.draw_disks(view, w, h, s.pos_radius, values_, pstyle);
  } else if (s.periodic[0] || s.periodic[1] || s.periodic[2]) {
    // Images across the periodic faces, each sphere's surface cut at the box (in the
    // sphere shader: 3D has no screen rectangle to scissor to).
    add_periodic_images(s, values_, wrapped_pos_, wrapped_values_);
    constexpr float kFar = 3e38f;
    std::array<float, 6> box{-kFar, -kFar, -kFar, kFar, kFar, kFar};
    for (int a = 0; a < 3; ++a)
      if (s.periodic[std::size_t(a)]) {
        box[std::size_t(a)] = float(s.lo[a]);
        box[std::size_t(a) + 3] = float(s.hi[a]);
      }
    pstyle.clip_box = box;
    particles_.draw_spheres(view, w, h, wrapped_pos_, wrapped_values_, pstyle);
  } else {
    particles_.draw_spheres(view, w, h, s.pos_radius, values_, pstyle);
  }
}

void FrameRenderer::draw_geometry(const Snapshot& s, const FrameStyle& style, const ViewTransform& view, int w,
                                  int h, bool plane_2d) {
  const Rgb edge = (style.background.r + style.background.g + style.background.b) > 1.5f ? Rgb{0.15f, 0.15f, 0.15f}
                                                                                          : Rgb{0.85f, 0.85f, 0.85f};
  geometry_.clear();
  if (s.dim == 2 || plane_2d) {
    // Obstacles: filled, then outlined, on top of the particles.
    if (!s.obstacles.empty()) {
      std::vector<float> obstacle_disks;
      for (const auto& c : s.obstacles)
        obstacle_disks.insert(obstacle_disks.end(), {float(c.centre.x()), float(c.centre.y()), 0.0f, float(c.radius)});
      ParticleDrawStyle flat{style.colormap, false, Rgb{0.55f, 0.55f, 0.58f}, std::nullopt};
      particles_.draw_disks(view, w, h, obstacle_disks, {}, flat);
      for (const auto& c : s.obstacles)
        add_circle(geometry_, c.centre.cast<float>(), float(c.radius), edge, 1.5f);
    }
    // Piston and filter: a line twice the outline's width, so they read as planes.
    for (const auto& l : s.boundary_lines)
      add_polyline(geometry_, {{float(l.a.x()), float(l.a.y()), 0.f}, {float(l.b.x()), float(l.b.y()), 0.f}}, edge,
                   3.0f);
    if (style.draw_domain) {
      const std::vector<Eigen::Vector3f> box = {{float(s.lo.x()), float(s.lo.y()), 0.f},
                                                {float(s.hi.x()), float(s.lo.y()), 0.f},
                                                {float(s.hi.x()), float(s.hi.y()), 0.f},
                                                {float(s.lo.x()), float(s.hi.y()), 0.f}};
      add_polyline(geometry_, box, edge, 1.5f, 1.0f, true);
    }
    segments_.draw(view, w, h, geometry_, false);
  } else {
    if (style.draw_domain) {
      std::array<BoxFace, 6> faces{};
      for (std::size_t f = 0; f < 6; ++f)
        faces[f] = s.periodic[f / 2] ? BoxFace::periodic : s.open_faces[f] ? BoxFace::open : BoxFace::wall;
      // The eye in world coordinates: the view is a rotation R and a translation t, eye = −Rᵀt.
      const Eigen::Matrix3d r = view.view.block<3, 3>(0, 0).cast<double>();
      const Eigen::Vector3d eye = -r.transpose() * view.view.block<3, 1>(0, 3).cast<double>();
      add_box(geometry_, s.lo, s.hi, faces, eye, edge, 2.0f);
    }
    segments_.draw(view, w, h, geometry_, true);
  }
}

const std::vector<std::optional<std::pair<double, double>>>& FrameRenderer::last_panel_ranges() const {
  static const std::vector<std::optional<std::pair<double, double>>> none;
  return panels_ ? panels_->last_ranges() : none;
}

}  // namespace grainflow::render
