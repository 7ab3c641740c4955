// EGL backend: a GPU through EGL devices when one exists, else Mesa's surfaceless
// platform (llvmpipe). Desktop GL core profile, 4.5 preferred, 3.3 the minimum our
// shaders need. No surface: the renderer draws into FBOs.
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstring>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "render/context/gl_context.hpp"

namespace grainflow::render {
namespace {

std::string egl_error_name(EGLint e) {
  switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    default: return "EGL error 0x" + std::to_string(e);
  }
}

bool has_extension(const char* list, const char* name) {
  if (!list) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)); p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

class EglContext final : public GlContext {
public:
  EglContext(EGLDisplay dpy, EGLContext ctx, std::string kind) : dpy_(dpy), ctx_(ctx), kind_(std::move(kind)) {
    make_current();
    gl_.load([](const char* name) { return reinterpret_cast<void*>(eglGetProcAddress(name)); });
  }
  ~EglContext() override {
    eglMakeCurrent(dpy_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(dpy_, ctx_);
    // No eglTerminate: Mesa hands every caller the same display, and terminating it
    // would invalidate other live contexts in this process.
  }
  std::string backend() const override { return kind_; }
  void make_current() override {
    if (!eglMakeCurrent(dpy_, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx_))
      throw Error("eglMakeCurrent failed: " + egl_error_name(eglGetError()));
  }

private:
  EGLDisplay dpy_;
  EGLContext ctx_;
  std::string kind_;
};

// Creates a core-profile context on an initialised display, or returns EGL_NO_CONTEXT.
EGLContext make_core_context(EGLDisplay dpy, std::string& why) {
  const char* exts = eglQueryString(dpy, EGL_EXTENSIONS);
  if (!has_extension(exts, "EGL_KHR_surfaceless_context")) {
    why = "display lacks EGL_KHR_surfaceless_context";
    return EGL_NO_CONTEXT;
  }
  if (!eglBindAPI(EGL_OPENGL_API)) {
    why = "desktop OpenGL API not supported by this EGL";
    return EGL_NO_CONTEXT;
  }
  EGLConfig config = EGL_NO_CONFIG_KHR;
  if (!has_extension(exts, "EGL_KHR_no_config_context")) {
    const EGLint cfg_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLint n = 0;
    if (!eglChooseConfig(dpy, cfg_attribs, &config, 1, &n) || n < 1) {
      why = "no EGL config with desktop OpenGL";
      return EGL_NO_CONTEXT;
    }
  }
  for (const auto& [major, minor] : {std::pair{4, 5}, std::pair{3, 3}}) {
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, major, EGL_CONTEXT_MINOR_VERSION, minor,
                              EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                              EGL_NONE};
    EGLContext ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, attribs);
    if (ctx != EGL_NO_CONTEXT) return ctx;
  }
  why = "cannot create a GL 3.3+ core context (" + egl_error_name(eglGetError()) + ")";
  return EGL_NO_CONTEXT;
}

}  // namespace

std::unique_ptr<GlContext> create_egl_context() {
  const char* client_exts = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!client_exts) throw Error("libEGL has no client extensions (EGL 1.5 with EXT_platform_base needed)");
  auto get_platform_display =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!get_platform_display) throw Error("eglGetPlatformDisplayEXT is missing");

  std::string why;
  // 1. A hardware device (a GPU), if EGL lists one: software devices are skipped here
  //    because the surfaceless platform below reaches the same llvmpipe.
  if (has_extension(client_exts, "EGL_EXT_device_enumeration") &&
      has_extension(client_exts, "EGL_EXT_platform_device")) {
    auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    auto query_device_string =
        reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    if (query_devices && query_device_string && query_devices(16, devices, &count)) {
      for (EGLint i = 0; i < count; ++i) {
        const char* dev_exts = query_device_string(devices[i], EGL_EXTENSIONS);
        if (has_extension(dev_exts, "EGL_MESA_device_software")) continue;
        EGLDisplay dpy = get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        EGLint major = 0, minor = 0;
        if (dpy == EGL_NO_DISPLAY || !eglInitialize(dpy, &major, &minor)) continue;
        EGLContext ctx = make_core_context(dpy, why);
        if (ctx != EGL_NO_CONTEXT) return std::make_unique<EglContext>(dpy, ctx, "egl-device");
      }
    }
  }
  // 2. Mesa's surfaceless platform.
  if (!has_extension(client_exts, "EGL_MESA_platform_surfaceless"))
    throw Error("EGL lacks EGL_MESA_platform_surfaceless (is Mesa's libegl-mesa0 installed?)");
  EGLDisplay dpy = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  EGLint major = 0, minor = 0;
  if (dpy == EGL_NO_DISPLAY || !eglInitialize(dpy, &major, &minor))
    throw Error("cannot initialise EGL surfaceless display (" + egl_error_name(eglGetError()) +
                "; Mesa's swrast driver comes with libgl1-mesa-dri)");
  EGLContext ctx = make_core_context(dpy, why);
  if (ctx == EGL_NO_CONTEXT) throw Error("EGL surfaceless: " + why);
  return std::make_unique<EglContext>(dpy, ctx, "egl-surfaceless");
}

}  // namespace grainflow::render
