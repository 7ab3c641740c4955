// Draws a Snapshot into an off-screen frame and reads it back as an Image: the one place
// that composes the layers (particles, domain, obstacles) for a frame — one full-frame
// picture, or a grid of panels with fields, titles, colour bars and a caption
// (render/panel_layout.hpp, drawn by render/panel_renderer.*).
#pragma once
#include <memory>
#include <optional>
#include <utility>

#include "render/context/framebuffer.hpp"
#include "render/context/gl_context.hpp"
#include "render/layers/camera.hpp"
#include "render/layers/colormap.hpp"
#include "render/layers/particle_layer.hpp"
#include "render/layers/segment_layer.hpp"
#include "render/panel_layout.hpp"
#include "render/snapshot.hpp"

namespace grainflow::render {

struct FrameStyle {
  Rgb background{1.0f, 1.0f, 1.0f};
  Colormap colormap{ColormapId::viridis};
  std::optional<std::pair<double, double>> range;  // colour range; automatic when empty
  OrbitCamera camera;                              // 3D only
  bool draw_domain = true;
};

// Range of the finite values (NaN/inf ignored); {0, 1} when there are none.
std::pair<double, double> finite_range(std::span<const float> values);

class PanelRenderer;

class FrameRenderer {
public:
  // The context must stay current on this thread while the renderer is used.
  FrameRenderer(GlContext& context, int width, int height, int msaa_samples = 0);
  ~FrameRenderer();

  // One picture filling the frame: particles, obstacles, domain.
  const Image& render(const Snapshot& snapshot, const FrameStyle& style);
  // A grid of panels. The first call loads the font (find_default_font(); throws
  // grainflow::Error when it is missing).
  const Image& render(const Snapshot& snapshot, const FrameStyle& style, const FrameLayout& layout);
  const Image& image() const { return image_; }
  // After a panel render: each panel's map range (PanelRenderer::last_ranges()); empty
  // before the first.
  const std::vector<std::optional<std::pair<double, double>>>& last_panel_ranges() const;
  // The particle layer, to choose its disk method or sphere culling (tests, benchmarks).
  ParticleLayer& particle_layer() { return particles_; }
  int width() const { return fb_.width(); }
  int height() const { return fb_.height(); }

private:
  friend class PanelRenderer;
  // Into the current viewport (width × height pixels) seen through `view`.
  void draw_particles(const Snapshot& s, const FrameStyle& style, const ViewTransform& view, int width, int height);
  // plane_2d: the x–y outline even for a 3D snapshot (field panels).
  void draw_geometry(const Snapshot& s, const FrameStyle& style, const ViewTransform& view, int width, int height,
                     bool plane_2d = false);
  ViewTransform scene_view(const Snapshot& s, const FrameStyle& style, int width, int height) const;

  GlContext& ctx_;
  Framebuffer fb_;
  ParticleLayer particles_;
  SegmentLayer segments_;
  Image image_;
  std::vector<float> values_;  // normalised attribute, reused across frames
  std::vector<float> wrapped_pos_, wrapped_values_;  // with periodic images, reused
  std::vector<Segment> geometry_;
  std::unique_ptr<PanelRenderer> panels_;
};

}  // namespace grainflow::render
