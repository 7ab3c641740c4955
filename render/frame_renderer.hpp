// Draws a Snapshot into an off-screen frame and reads it back as an Image: the one place
// that composes the layers (particles, domain, obstacles) for a frame.
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

class FrameRenderer {
public:
  // The context must stay current on this thread while the renderer is used.
  FrameRenderer(GlContext& context, int width, int height, int msaa_samples = 0);

  const Image& render(const Snapshot& snapshot, const FrameStyle& style);
  const Image& image() const { return image_; }
  int width() const { return fb_.width(); }
  int height() const { return fb_.height(); }

private:
  GlContext& ctx_;
  Framebuffer fb_;
  ParticleLayer particles_;
  SegmentLayer segments_;
  Image image_;
  std::vector<float> values_;  // normalised attribute, reused across frames
  std::vector<Segment> geometry_;
};

}  // namespace grainflow::render
