// The picture outputs: DIR/frames/frame_NNNNNN.png and DIR/<scene>.mp4 (H.264), fed with
// the rendered frames through render's sinks (each on its own encoding thread).
#include <filesystem>
#include <string>

#include "engine/core/error.hpp"

#include "render/output/mp4_sink.hpp"
#include "render/output/png_sequence_sink.hpp"
#include "scenes/src/outputs/output_table.hpp"
#include "scenes/src/outputs/video_keys.hpp"
#include "scenes/src/scene/scene.hpp"

namespace grainflow::scenes {
namespace {

constexpr Key<bool> png{"output.png"};
constexpr Key<bool> mp4{"output.mp4"};
using video_keys::fps;
constexpr Key<std::int64_t> crf{"output.crf"};
constexpr Key<std::string> preset{"output.preset"};
constexpr Key<std::string> chroma{"output.chroma"};

void declare_png(Schema& s) { s.table("output").add_bool(png, true, "write frames/frame_NNNNNN.png"); }

std::unique_ptr<render::FrameSink> open_png(const OutputContext& c) {
  if (!c.scene.get(png)) return nullptr;
  c.claim(kFrameFiles);
  return std::make_unique<render::PngSequenceSink>(c.dir / "frames");
}

void declare_mp4(Schema& s) {
  auto& out = s.table("output");
  out.add_bool(mp4, true, "write an H.264 MP4 of the frames");
  // No default: a scene that gives no rate gets one from output.video_seconds.
  out.add_int(fps, 30,
              "MP4 frame rate (not given: a rate that makes the video last about output.video_seconds, written to "
              "DIR/scene.toml; 30 when the run is given in run.steps)",
              "frames/s")
      .optional()
      .at_least(1)
      .at_most(240);
  out.add_int(crf, 20, "H.264 constant rate factor (lower = better quality, larger file)").at_least(0).at_most(51);
  out.add_enum(preset, {"ultrafast", "superfast", "veryfast", "faster", "fast", "medium", "slow", "slower", "veryslow"},
               "medium", "H.264 encoder speed/size preset");
  out.add_enum(chroma, {"4:2:0", "4:4:4"}, "4:2:0",
               "colour resolution: 4:2:0 plays everywhere but halves it (1-pixel disks and bin edges smear); 4:4:4 "
               "keeps it for analysis copies (with output.crf = 0: lossless; ffmpeg, VLC and mpv play it, browsers "
               "often do not)");
}

std::unique_ptr<render::FrameSink> open_mp4(const OutputContext& c) {
  if (!c.scene.get(mp4)) return nullptr;
  c.claim(c.name + ".mp4");
  render::Mp4Options opt;
  opt.fps = int(c.scene.find(fps).value_or(30));
  opt.crf = int(c.scene.get(crf));
  opt.preset = c.scene.get(preset);
  opt.chroma_444 = c.scene.get(chroma) == "4:4:4";
  const std::filesystem::path file = c.dir / (c.name + ".mp4");
  if (c.resume_frames && *c.resume_frames > 0) {
    // The video continues from its first K frames: in the .partial a killed run left, or
    // in the MP4 an interrupted run finished (which becomes the .partial again).
    std::filesystem::path partial = file;
    partial += ".partial";
    std::error_code ec;
    if (!std::filesystem::exists(partial, ec) && std::filesystem::exists(file, ec)) {
      std::filesystem::rename(file, partial, ec);
      if (ec) throw Error("cannot continue '" + file.string() + "': " + ec.message());
    }
    opt.resume_frames = *c.resume_frames;
  }
  return std::make_unique<render::Mp4Sink>(file, opt);
}

}  // namespace

OutputEntry png_output() { return {"png", "frames/frame_NNNNNN.png, one per frame", &declare_png, &open_png, nullptr}; }
OutputEntry mp4_output() { return {"mp4", "<scene>.mp4, H.264 of the frames", &declare_mp4, &open_mp4, nullptr}; }

}  // namespace grainflow::scenes
