#include "render/context/framebuffer.hpp"

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "engine/core/error.hpp"

namespace grainflow::render {
namespace {
void check_complete(const GlApi& gl, const char* what) {
  const GLenum status = gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw Error(std::string(what) + " framebuffer incomplete (status 0x" + std::to_string(status) + ")");
}
}  // namespace

Framebuffer::Framebuffer(const GlApi& gl, int width, int height, int samples)
    : gl_(gl), width_(width), height_(height), samples_(0) {
  GLint max_size = 0, max_samples = 0;
  gl_.GetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
  gl_.GetIntegerv(GL_MAX_SAMPLES, &max_samples);
  if (width < 1 || height < 1 || width > max_size || height > max_size)
    throw Error("image size " + std::to_string(width) + "x" + std::to_string(height) +
                " is outside what this GL allows (1.." + std::to_string(max_size) + " per side)");
  samples_ = samples > 1 ? std::min(samples, static_cast<int>(max_samples)) : 0;

  gl_.GenFramebuffers(1, &fbo_);
  gl_.BindFramebuffer(GL_FRAMEBUFFER, fbo_);
  gl_.GenRenderbuffers(1, &colour_);
  gl_.BindRenderbuffer(GL_RENDERBUFFER, colour_);
  if (samples_) gl_.RenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, GL_RGBA8, width, height);
  else gl_.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
  gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_);
  gl_.GenRenderbuffers(1, &depth_);
  gl_.BindRenderbuffer(GL_RENDERBUFFER, depth_);
  if (samples_) gl_.RenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, GL_DEPTH_COMPONENT24, width, height);
  else gl_.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
  gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  check_complete(gl_, "render");

  if (samples_) {
    gl_.GenFramebuffers(1, &resolve_fbo_);
    gl_.BindFramebuffer(GL_FRAMEBUFFER, resolve_fbo_);
    gl_.GenRenderbuffers(1, &resolve_colour_);
    gl_.BindRenderbuffer(GL_RENDERBUFFER, resolve_colour_);
    gl_.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolve_colour_);
    check_complete(gl_, "resolve");
  }
  bind();
}

Framebuffer::~Framebuffer() {
  gl_.BindFramebuffer(GL_FRAMEBUFFER, 0);
  const GLuint rbs[] = {colour_, depth_, resolve_colour_};
  gl_.DeleteRenderbuffers(3, rbs);
  const GLuint fbos[] = {fbo_, resolve_fbo_};
  gl_.DeleteFramebuffers(2, fbos);
}

void Framebuffer::bind() {
  gl_.BindFramebuffer(GL_FRAMEBUFFER, fbo_);
  gl_.Viewport(0, 0, width_, height_);
}

void Framebuffer::read(Image& out) {
  GLuint source = fbo_;
  if (samples_) {
    gl_.BindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
    gl_.BindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fbo_);
    gl_.BlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    source = resolve_fbo_;
  }
  gl_.BindFramebuffer(GL_READ_FRAMEBUFFER, source);
  gl_.ReadBuffer(GL_COLOR_ATTACHMENT0);
  gl_.PixelStorei(GL_PACK_ALIGNMENT, 1);
  if (out.width != width_ || out.height != height_) out = Image(width_, height_);
  gl_.ReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, out.rgba.data());
  // GL rows go bottom-up; images top-down.
  const std::size_t row = static_cast<std::size_t>(width_) * 4;
  std::vector<std::uint8_t> tmp(row);
  for (int y = 0; y < height_ / 2; ++y) {
    auto* a = out.rgba.data() + y * row;
    auto* b = out.rgba.data() + (height_ - 1 - y) * row;
    std::memcpy(tmp.data(), a, row);
    std::memcpy(a, b, row);
    std::memcpy(b, tmp.data(), row);
  }
  bind();
}

}  // namespace grainflow::render
