// A linked GLSL program built from the shaders embedded from assets/shaders/ at build
// time (so the binary needs no asset directory at run time).
#pragma once
#include <string>
#include <string_view>

#include "render/context/gl_api.hpp"

namespace grainflow::render {

// Text of assets/shaders/<name>, embedded in the binary; throws if unknown.
std::string_view shader_source(std::string_view name);

class ShaderProgram {
public:
  // Compiles and links; throws grainflow::Error with the driver's log on failure.
  // `defines` (e.g. "#define QUADS\n") is inserted after each shader's #version line, so
  // one shader file serves several variants.
  ShaderProgram(const GlApi& gl, std::string_view vertex_name, std::string_view fragment_name,
                std::string_view defines = {});
  ~ShaderProgram();
  ShaderProgram(const ShaderProgram&) = delete;
  ShaderProgram& operator=(const ShaderProgram&) = delete;

  void use() const { gl_.UseProgram(id_); }
  GLint uniform(const char* name) const { return gl_.GetUniformLocation(id_, name); }
  GLuint id() const { return id_; }

private:
  const GlApi& gl_;
  GLuint id_ = 0;
};

}  // namespace grainflow::render
