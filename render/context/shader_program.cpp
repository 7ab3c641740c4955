#include "render/context/shader_program.hpp"

#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "render/context/embedded_shaders.hpp"

namespace grainflow::render {

std::string_view shader_source(std::string_view name) {
  for (const auto& s : embedded_shaders())
    if (s.name == name) return s.text;
  throw Error("no embedded shader named '" + std::string(name) + "'");
}

namespace {
GLuint compile(const GlApi& gl, GLenum type, std::string_view name, std::string_view defines) {
  std::string text(shader_source(name));
  const auto eol = text.find('\n');
  if (!defines.empty() && eol != std::string::npos) text.insert(eol + 1, defines);
  const GLuint sh = gl.CreateShader(type);
  const char* src = text.data();
  const GLint len = static_cast<GLint>(text.size());
  gl.ShaderSource(sh, 1, &src, &len);
  gl.CompileShader(sh);
  GLint ok = 0;
  gl.GetShaderiv(sh, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint n = 0;
    gl.GetShaderiv(sh, GL_INFO_LOG_LENGTH, &n);
    std::string log(static_cast<std::size_t>(std::max(n, 1)), '\0');
    gl.GetShaderInfoLog(sh, n, nullptr, log.data());
    gl.DeleteShader(sh);
    throw Error("shader " + std::string(name) + " does not compile: " + log);
  }
  return sh;
}
}  // namespace

ShaderProgram::ShaderProgram(const GlApi& gl, std::string_view vertex_name, std::string_view fragment_name,
                             std::string_view defines)
    : gl_(gl) {
  const GLuint vs = compile(gl, GL_VERTEX_SHADER, vertex_name, defines);
  const GLuint fs = compile(gl, GL_FRAGMENT_SHADER, fragment_name, defines);
  id_ = gl.CreateProgram();
  gl.AttachShader(id_, vs);
  gl.AttachShader(id_, fs);
  gl.LinkProgram(id_);
  gl.DeleteShader(vs);
  gl.DeleteShader(fs);
  GLint ok = 0;
  gl.GetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint n = 0;
    gl.GetProgramiv(id_, GL_INFO_LOG_LENGTH, &n);
    std::string log(static_cast<std::size_t>(std::max(n, 1)), '\0');
    gl.GetProgramInfoLog(id_, n, nullptr, log.data());
    gl.DeleteProgram(id_);
    throw Error("shaders " + std::string(vertex_name) + " + " + std::string(fragment_name) +
                " do not link: " + log);
  }
}

ShaderProgram::~ShaderProgram() { gl_.DeleteProgram(id_); }

}  // namespace grainflow::render
