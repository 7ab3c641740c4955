#include "render/context/gl_context.hpp"

#include <string>

#include "engine/core/error.hpp"

namespace grainflow::render {

Backend parse_backend(std::string_view name) {
  if (name == "auto") return Backend::Auto;
  if (name == "egl") return Backend::Egl;
  if (name == "osmesa") return Backend::OSMesa;
  throw Error("unknown backend '" + std::string(name) + "' (allowed: auto, egl, osmesa)");
}

std::string_view backend_name(Backend b) {
  switch (b) {
    case Backend::Auto: return "auto";
    case Backend::Egl: return "egl";
    case Backend::OSMesa: return "osmesa";
  }
  return "?";
}

namespace {
std::string gl_string(const GlApi& gl, GLenum what) {
  const auto* s = gl.GetString(what);
  return s ? reinterpret_cast<const char*>(s) : std::string("(null)");
}
}  // namespace

std::string GlContext::gl_version() const { return gl_string(gl_, GL_VERSION); }
std::string GlContext::gl_renderer() const { return gl_string(gl_, GL_RENDERER); }
std::string GlContext::gl_vendor() const { return gl_string(gl_, GL_VENDOR); }
std::string GlContext::glsl_version() const { return gl_string(gl_, GL_SHADING_LANGUAGE_VERSION); }
int GlContext::max_samples() const {
  GLint n = 0;
  gl_.GetIntegerv(GL_MAX_SAMPLES, &n);
  return n;
}

std::unique_ptr<GlContext> create_context(Backend backend, std::string* notice) {
  if (backend == Backend::Egl) return create_egl_context();
  if (backend == Backend::OSMesa) return create_osmesa_context();
  std::string egl_error;
  try {
    return create_egl_context();
  } catch (const Error& e) {
    egl_error = e.what();
  }
  try {
    auto ctx = create_osmesa_context();
    if (notice) *notice = "EGL unavailable (" + egl_error + "); using OSMesa";
    return ctx;
  } catch (const Error& e) {
    throw Error("no OpenGL backend works here.\n  egl: " + egl_error + "\n  osmesa: " + e.what() +
                "\n  (on Debian: apt-get install libegl-mesa0 libgl1-mesa-dri libosmesa6)");
  }
}

}  // namespace grainflow::render
