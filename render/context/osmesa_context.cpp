// OSMesa backend: Mesa's off-screen library, core profile. Used when EGL is missing.
// OSMesa needs a bound colour buffer to make a context current; we give it 1×1 pixel
// and draw into FBOs like the EGL backend does.
// glcorearb.h (through gl_context.hpp) must come before osmesa.h: osmesa.h pulls in
// GL/gl.h, which would hide glcorearb's GL 1.x function-pointer typedefs.
#include "render/context/gl_context.hpp"
// clang-format off
#include <GL/osmesa.h>
// clang-format on

#include <array>
#include <string>

#include "engine/core/error.hpp"

namespace grainflow::render {
namespace {

class OSMesaGlContext final : public GlContext {
public:
  explicit OSMesaGlContext(OSMesaContext ctx) : ctx_(ctx) {
    make_current();
    gl_.load([](const char* name) { return reinterpret_cast<void*>(OSMesaGetProcAddress(name)); });
  }
  ~OSMesaGlContext() override { OSMesaDestroyContext(ctx_); }
  std::string backend() const override { return "osmesa"; }
  void make_current() override {
    if (!OSMesaMakeCurrent(ctx_, dummy_.data(), GL_UNSIGNED_BYTE, 1, 1))
      throw Error("OSMesaMakeCurrent failed");
  }

private:
  OSMesaContext ctx_;
  std::array<unsigned char, 4> dummy_{};
};

}  // namespace

std::unique_ptr<GlContext> create_osmesa_context() {
  for (const auto& [major, minor] : {std::pair{4, 5}, std::pair{3, 3}}) {
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                           OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION, major, OSMESA_CONTEXT_MINOR_VERSION, minor, 0};
    OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, nullptr);
    if (ctx) return std::make_unique<OSMesaGlContext>(ctx);
  }
  throw Error("OSMesa cannot create a GL 3.3+ core context (libOSMesa from libosmesa6)");
}

}  // namespace grainflow::render
