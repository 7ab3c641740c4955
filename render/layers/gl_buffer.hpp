// Small RAII owners of GL objects used by the layers: a growable vertex buffer and a
// vertex array. Uploads reuse the buffer's storage when it is large enough.
#pragma once
#include <cstddef>

#include "render/context/gl_api.hpp"

namespace grainflow::render {

class GlBuffer {
public:
  explicit GlBuffer(const GlApi& gl) : gl_(gl) { gl_.GenBuffers(1, &id_); }
  ~GlBuffer() { gl_.DeleteBuffers(1, &id_); }
  GlBuffer(const GlBuffer&) = delete;
  GlBuffer& operator=(const GlBuffer&) = delete;

  void upload(const void* data, std::size_t bytes) {
    gl_.BindBuffer(GL_ARRAY_BUFFER, id_);
    if (bytes > capacity_) {
      gl_.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(bytes), data, GL_STREAM_DRAW);
      capacity_ = bytes;
    } else if (bytes > 0) {
      gl_.BufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(bytes), data);
    }
  }
  GLuint id() const { return id_; }

private:
  const GlApi& gl_;
  GLuint id_ = 0;
  std::size_t capacity_ = 0;
};

class GlVertexArray {
public:
  explicit GlVertexArray(const GlApi& gl) : gl_(gl) { gl_.GenVertexArrays(1, &id_); }
  ~GlVertexArray() { gl_.DeleteVertexArrays(1, &id_); }
  GlVertexArray(const GlVertexArray&) = delete;
  GlVertexArray& operator=(const GlVertexArray&) = delete;
  void bind() const { gl_.BindVertexArray(id_); }

private:
  const GlApi& gl_;
  GLuint id_ = 0;
};

class GlTexture {
public:
  explicit GlTexture(const GlApi& gl) : gl_(gl) { gl_.GenTextures(1, &id_); }
  ~GlTexture() { gl_.DeleteTextures(1, &id_); }
  GlTexture(const GlTexture&) = delete;
  GlTexture& operator=(const GlTexture&) = delete;
  GLuint id() const { return id_; }

private:
  const GlApi& gl_;
  GLuint id_ = 0;
};

}  // namespace grainflow::render
