// `grainflow info`: what this build can do here — engines, GL backends with their GL
// version and renderer strings, and the library versions it runs with.
#include <png.h>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libswscale/swscale.h>
}

#include <cstdio>
#include <string>

#include "engine/core/error.hpp"
#include "render/context/gl_context.hpp"
#include "scenes/src/cli/commands.hpp"
#include "scenes/src/engines/engine_table.hpp"

namespace grainflow::scenes {
namespace {

std::string av_version(unsigned v) {
  return std::to_string(v >> 16) + "." + std::to_string((v >> 8) & 0xff) + "." + std::to_string(v & 0xff);
}

void print_backend(const char* name, std::unique_ptr<render::GlContext> (*create)()) {
  try {
    auto ctx = create();
    std::printf("  %-7s ok: %s | GL %s | GLSL %s | max MSAA %d\n", name, ctx->backend().c_str(),
                ctx->gl_version().c_str(), ctx->glsl_version().c_str(), ctx->max_samples());
    std::printf("          renderer: %s (%s)\n", ctx->gl_renderer().c_str(), ctx->gl_vendor().c_str());
  } catch (const Error& e) {
    std::printf("  %-7s unavailable: %s\n", name, e.what());
  }
}

}  // namespace

void setup_info_command(CLI::App& app, int& status) {
  auto* cmd = app.add_subcommand("info", "Print engines, GL backends and library versions");
  cmd->callback([&status] {
    std::printf("grainflow %s\n", GRAINFLOW_VERSION);
    std::printf("engines:\n");
    for (const auto& k : engines())
      std::printf("  %-7.*s %.*s\n", int(k.name.size()), k.name.data(), int(k.description.size()),
                  k.description.data());
    std::printf("GL backends (--backend auto tries egl, then osmesa):\n");
    print_backend("egl", &render::create_egl_context);
    print_backend("osmesa", &render::create_osmesa_context);
    std::printf("libraries:\n");
    std::printf("  libpng     %s\n", png_get_libpng_ver(nullptr));
    std::printf("  libavcodec %s, libavformat %s, libswscale %s (FFmpeg %s)\n",
                av_version(avcodec_version()).c_str(), av_version(avformat_version()).c_str(),
                av_version(swscale_version()).c_str(), av_version_info());
    const AVCodec* x264 = avcodec_find_encoder_by_name("libx264");
    std::printf("  H.264 encoder: %s\n", x264 ? "libx264" : "missing (MP4 output unavailable)");
    status = 0;
  });
}

}  // namespace grainflow::scenes
