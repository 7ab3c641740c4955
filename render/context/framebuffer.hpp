// The off-screen render target: an FBO with colour (RGBA8) and depth, optionally
// multisampled (resolved by a blit before read-back). read() returns the picture top row
// first, fixing GL's bottom-up row order in this one place.
#pragma once
#include "render/context/gl_context.hpp"
#include "render/image/image.hpp"

namespace grainflow::render {

class Framebuffer {
public:
  // Throws grainflow::Error for sizes outside [1, GL_MAX_RENDERBUFFER_SIZE] or an
  // incomplete framebuffer. samples = 0 or 1: no MSAA; clamped to GL_MAX_SAMPLES.
  Framebuffer(const GlApi& gl, int width, int height, int samples = 0);
  ~Framebuffer();
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;

  void bind();                // draw target for subsequent GL calls, full viewport
  void read(Image& out);      // resolve (if MSAA) and read back; out is resized
  int width() const { return width_; }
  int height() const { return height_; }
  int samples() const { return samples_; }

private:
  const GlApi& gl_;
  int width_, height_, samples_;
  GLuint fbo_ = 0, colour_ = 0, depth_ = 0;
  GLuint resolve_fbo_ = 0, resolve_colour_ = 0;  // only with MSAA
};

}  // namespace grainflow::render
