// Off-screen OpenGL contexts: sibling backends (EGL on Mesa's surfaceless platform or an
// EGL device; OSMesa) behind one interface, chosen at run time (`--backend`). A context
// has no window: everything is drawn into framebuffer objects (render/context/framebuffer).
#pragma once
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "render/context/gl_api.hpp"

namespace grainflow::render {

enum class Backend { Auto, Egl, OSMesa };

// "auto" | "egl" | "osmesa"; throws grainflow::Error listing the allowed names otherwise.
Backend parse_backend(std::string_view name);
std::string_view backend_name(Backend b);

class GlContext {
public:
  virtual ~GlContext() = default;
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  // "egl-device", "egl-surfaceless" or "osmesa": what actually runs.
  virtual std::string backend() const = 0;
  // Makes this context current on the calling thread.
  virtual void make_current() = 0;

  const GlApi& gl() const { return gl_; }
  std::string gl_version() const;
  std::string gl_renderer() const;
  std::string gl_vendor() const;
  std::string glsl_version() const;
  int max_samples() const;

protected:
  GlContext() = default;
  GlApi gl_;
};

// One attempt per backend; `Auto` tries EGL then OSMesa and writes a one-line notice to
// `notice` when it had to fall back. Throws grainflow::Error naming what failed for every
// backend tried (e.g. the missing library or driver) when none works.
std::unique_ptr<GlContext> create_context(Backend backend, std::string* notice = nullptr);

// Created per backend; exposed for `grainflow info` and tests.
std::unique_ptr<GlContext> create_egl_context();     // throws grainflow::Error
std::unique_ptr<GlContext> create_osmesa_context();  // throws grainflow::Error

}  // namespace grainflow::render
