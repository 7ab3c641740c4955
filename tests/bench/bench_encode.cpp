// Encoding throughput of the output sinks at 1920x1080: PNG (fast and default zlib
// settings), H.264 per x264 preset, and how much AsyncSink hides behind a busy producer.
// Usage: bench_encode [frames-per-mp4-run=60] [scratch-dir=/tmp/grainflow_bench_encode]
//                     [presets, comma-separated: only these MP4 rows, no PNG or overlap]
//        bench_encode sync [frames=300] [every=30] [scratch-dir]
//                     checkpoints: the cost of Mp4Writer::sync() and of a resume (see
//                     sync_bench below), at 1280x720 and 1920x1080, default options.
// "finish ms" is Mp4Sink::finish(): x264's delayed frames, then (since #12) the copy of the
// fragmented .partial into the standard MP4, whose cost it shows.
//
// Fault-safe MP4 (#12): `bench_encode 40 DIR superfast` (and 300), medians of 3 runs
// alternating with the same bench built on the previous writer, on the shared 2-core machine
// (load ~2.5 from other work, so wall frames/s is noisy; CPU ms/frame is the steadier figure):
//                                     frames/s  CPU ms/f  finish ms  bytes (40 / 300 frames)
//   before: one moov, +faststart        22.1      45.7      267      5108099 / 36771655
//   fragment per frame + standard copy  21.2      47.0      279      5108046 / 36771602
//   fragments at keyframes, keyint 30   21.7      46.3      257      5293698 / 38195303
// The finished file is the previous one's packets, 53 bytes lighter (no "Lavf" tag); the
// .partial is 118 bytes a frame more (36806886 at 300 frames). A kill loses the 9 frames
// inside x264 (frame per fragment) against up to 30 + 9 (keyint 30, +3.6..3.9% in size),
// or the whole video before. The copy at finish: ~50 ms for the 37 MB of 300 frames.

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "engine/core/rng.hpp"
#include "render/image/image.hpp"
#include "render/output/async_sink.hpp"
#include "render/output/mp4_sink.hpp"
#include "render/output/mp4_writer.hpp"
#include "render/output/png_io.hpp"
#include "render/output/png_sequence_sink.hpp"
#include "tests/bench/bench_args.hpp"

namespace {

using grainflow::render::Image;
using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;
namespace bench = grainflow::bench;
constexpr const char* kUsage =
    "bench_encode [frames-per-mp4-run=60] [scratch-dir=/tmp/grainflow_bench_encode] [presets,comma-separated]\n"
    "       bench_encode sync [frames=300] [every=30] [scratch-dir=/tmp/grainflow_bench_encode_sync]\n"
    "(a scratch folder must be new, or one a benchmark made: it is emptied and removed)";

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// CPU seconds used by all threads of this process (encoder threads included). On a
// shared machine wall time depends on the neighbours; CPU time per frame does not, and
// bounds what an idle machine could do: frames/s <= threads / cpu-seconds-per-frame.
double process_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

struct Disk {
  double x, y, vx, vy, r;
  std::uint8_t c[3];
};

// A granular-looking frame: shaded background, a few thousand anti-aliased coloured disks
// with a dark rim, moving a little each frame — detail and motion like a real run's frames,
// unlike a flat colour that every encoder compresses for free.
std::vector<Image> make_frames(int w, int h, int count) {
  grainflow::core::Rng rng(2024);
  std::vector<Disk> disks(3500);
  for (auto& d : disks) {
    d.x = rng.uniform(0, w);
    d.y = rng.uniform(0, h);
    d.vx = rng.normal(0, 2.0);
    d.vy = rng.normal(0, 2.0);
    d.r = rng.uniform(5, 12);
    const double t = rng.uniform();  // colour by a "speed" attribute along a warm ramp
    d.c[0] = static_cast<std::uint8_t>(60 + 195 * t);
    d.c[1] = static_cast<std::uint8_t>(40 + 150 * t * t);
    d.c[2] = static_cast<std::uint8_t>(200 - 170 * t);
  }
  std::vector<Image> frames;
  for (int k = 0; k < count; ++k) {
    Image im(w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        std::uint8_t* p = im.pixel(x, y);
        const double g = 0.5 + 0.5 * std::sin(0.004 * x + 0.006 * y + 0.05 * k);
        p[0] = static_cast<std::uint8_t>(20 + 25 * g);
        p[1] = static_cast<std::uint8_t>(24 + 20 * g);
        p[2] = static_cast<std::uint8_t>(35 + 30 * g);
        p[3] = 255;
      }
    for (auto& d : disks) {
      d.x += d.vx;
      d.y += d.vy;
      const int x0 = std::max(0, int(d.x - d.r - 1)), x1 = std::min(w - 1, int(d.x + d.r + 1));
      const int y0 = std::max(0, int(d.y - d.r - 1)), y1 = std::min(h - 1, int(d.y + d.r + 1));
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const double dist = std::hypot(x + 0.5 - d.x, y + 0.5 - d.y);
          const double cover = std::clamp(d.r - dist + 0.5, 0.0, 1.0);
          if (cover <= 0) continue;
          const double shade = dist > d.r - 1.5 ? 0.45 : 1.0 - 0.35 * dist / d.r;
          std::uint8_t* p = im.pixel(x, y);
          for (int c = 0; c < 3; ++c)
            p[c] = static_cast<std::uint8_t>(std::lround((1 - cover) * p[c] + cover * shade * d.c[c]));
        }
    }
    frames.push_back(std::move(im));
  }
  return frames;
}

// Frames ping-pong through the stored set, so motion stays continuous without storing
// hundreds of 8 MB frames.
const Image& frame_at(const std::vector<Image>& f, int k) {
  const int n = int(f.size()), period = 2 * n - 2;
  const int m = k % period;
  return f[m < n ? m : period - m];
}

// Stands in for simulation + rendering: a fixed amount of CPU work per frame.
void busy(double seconds) {
  const auto t0 = Clock::now();
  volatile double x = 0;
  while (seconds_since(t0) < seconds) x = x + 1.0;
}

// Checkpoints (`grainflow run --resume`), default MP4 options (superfast, crf 20, 2 threads):
//  - "no sync" / "sync every N": the same `frames` frames encoded without and with a
//    sync() every N frames: wall and CPU per frame, final MP4 size, and each sync()'s wall
//    time (drain x264's pipeline, write those fragments, open a new x264 instance).
//  - "resume copy": a writer resumed at `frames` from the .partial that the synced run left
//    (with 10 frames past the checkpoint, as after a kill): the constructor's time, which is
//    the copy of the packets plus opening x264; "open" is a plain writer's constructor, for
//    comparison.
int sync_bench(int argc, char** argv) {
  using namespace grainflow::render;
  bench::at_most("bench_encode", kUsage, argc, argv, 4);
  const int frames = argc > 2 ? static_cast<int>(bench::number_arg("bench_encode", kUsage, "frames", argv[2], 30, 1e5, true)) : 300;
  const int every = argc > 3 ? static_cast<int>(bench::number_arg("bench_encode", kUsage, "every", argv[3], 1, 1e5, true)) : 30;
  const bench::ScratchDir scratch("bench_encode", argc > 4 ? fs::path(argv[4]) : fs::path("/tmp/grainflow_bench_encode_sync"));
  const fs::path& dir = scratch.path();
  std::printf("bench_encode sync: %d frames, sync every %d, default MP4 options, scratch %s\n", frames, every,
              dir.c_str());
  for (const auto& [W, H] : {std::pair{1280, 720}, std::pair{1920, 1080}}) {
    const std::vector<Image> src = make_frames(W, H, 16);
    std::printf("\n%dx%d\n%-22s %10s %10s %14s %12s %30s\n", W, H, "case", "wall ms/f", "CPU ms/f", "MP4 bytes",
                "finish ms", "sync() ms: mean / min / max");
    std::uintmax_t base_bytes = 0;
    for (const int interval : {0, every}) {
      const fs::path p = dir / (std::to_string(W) + (interval ? "_sync.mp4" : "_plain.mp4"));
      std::vector<double> syncs;
      const double cpu0 = process_cpu_seconds();
      const auto t0 = Clock::now();
      double finish_s = 0;
      {
        Mp4Writer w(p, W, H);
        for (int k = 0; k < frames; ++k) {
          w.write(frame_at(src, k));
          if (interval && (k + 1) % interval == 0 && k + 1 < frames) {
            const auto ts = Clock::now();
            w.sync();
            syncs.push_back(seconds_since(ts));
          }
        }
        const auto tf = Clock::now();
        w.finish();
        finish_s = seconds_since(tf);
      }
      const double wall = seconds_since(t0), cpu = process_cpu_seconds() - cpu0;
      const std::uintmax_t bytes = fs::file_size(p);
      if (!interval) base_bytes = bytes;
      const std::string name = interval ? "sync every " + std::to_string(interval) : "no sync";
      std::printf("%-22s %10.1f %10.1f %14ju %12.1f", name.c_str(), 1e3 * wall / frames, 1e3 * cpu / frames, bytes,
                  1e3 * finish_s);
      if (!syncs.empty()) {
        double sum = 0;
        for (double x : syncs) sum += x;
        std::printf("   %8.1f / %6.1f / %6.1f (%zu)", 1e3 * sum / double(syncs.size()),
                    1e3 * *std::min_element(syncs.begin(), syncs.end()),
                    1e3 * *std::max_element(syncs.begin(), syncs.end()), syncs.size());
        std::printf("\n%-22s size %+.2f%% (%+.0f bytes per sync)", "", 100.0 * (double(bytes) - double(base_bytes)) / double(base_bytes),
                    (double(bytes) - double(base_bytes)) / double(syncs.size()));
      }
      std::printf("\n");
      std::fflush(stdout);
    }
    // The run a resume continues: synced at `frames`, 10 frames past it, then "killed"
    // (dropped unfinished: the frames x264 held are flushed, as far as a kill gets).
    const fs::path p = dir / (std::to_string(W) + "_resume.mp4");
    {
      Mp4Writer w(p, W, H);
      for (int k = 0; k < frames; ++k) w.write(frame_at(src, k));
      w.sync();
      for (int k = frames; k < frames + 10; ++k) w.write(frame_at(src, k));
    }
    const std::uintmax_t partial_bytes = fs::file_size(p.string() + ".partial");
    double open_s = 0, resume_s = 0;
    {
      const auto t0 = Clock::now();
      Mp4Writer plain(dir / "open.mp4", W, H);
      open_s = seconds_since(t0);
    }
    {
      Mp4Options o;
      o.resume_frames = frames;
      const auto t0 = Clock::now();
      Mp4Writer resumed(p, W, H, o);
      resume_s = seconds_since(t0);
      for (int k = frames; k < frames + 10; ++k) resumed.write(frame_at(src, k));
      resumed.finish();
    }
    std::printf("%-22s %10.1f ms for %d frames (%.1f MB .partial); a plain writer opens in %.1f ms\n",
                "resume copy", 1e3 * resume_s, frames, double(partial_bytes) / 1e6, 1e3 * open_s);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace grainflow::render;
  if (argc > 1 && std::string(argv[1]) == "sync") return sync_bench(argc, argv);
  if (argc > 1 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h")) {
    std::printf("usage: %s\n", kUsage);
    return 0;
  }
  bench::at_most("bench_encode", kUsage, argc, argv, 3);
  const int mp4_frames =
      argc > 1 ? static_cast<int>(bench::number_arg("bench_encode", kUsage, "frames", argv[1], 10, 1e5, true)) : 60;
  std::vector<std::string> presets = {"ultrafast", "superfast", "veryfast", "fast", "medium"};
  const bool mp4_only = argc > 3;
  if (mp4_only) {
    presets.clear();
    for (std::string list = argv[3]; !list.empty();) {
      const auto comma = list.find(',');
      presets.push_back(list.substr(0, comma));
      list = comma == std::string::npos ? "" : list.substr(comma + 1);
    }
  }
  const bench::ScratchDir scratch("bench_encode", argc > 2 ? fs::path(argv[2]) : fs::path("/tmp/grainflow_bench_encode"));
  const fs::path& dir = scratch.path();
  const int W = 1920, H = 1080;
  std::printf("bench_encode: %dx%d RGBA frames (3500 moving shaded disks on a gradient), scratch %s\n", W, H,
              dir.c_str());
  const auto tgen = Clock::now();
  const std::vector<Image> frames = make_frames(W, H, 16);
  std::printf("  generated %zu distinct frames in %.1f s\n\n", frames.size(), seconds_since(tgen));

  std::printf("%-40s %10s %10s %12s %12s %10s\n", "case", "wall ms/f", "frames/s", "CPU ms/f", "size/frame",
              "finish ms");
  double cpu0 = 0.0;
  const auto row = [&cpu0](const std::string& name, double sec, int n, double bytes, double finish_s = -1) {
    const double cpu = process_cpu_seconds() - cpu0;
    std::printf("%-40s %10.1f %10.1f %12.1f %10.3f MB", name.c_str(), 1e3 * sec / n, n / sec, 1e3 * cpu / n,
                bytes / n / 1e6);
    if (finish_s >= 0) std::printf(" %10.1f", 1e3 * finish_s);
    std::printf("\n");
    std::fflush(stdout);
  };

  // PNG
  if (!mp4_only) {
    for (const PngOptions opt : {PngOptions{1, false}, PngOptions{6, true}}) {
      const int n = opt.compression_level == 1 ? 16 : 6;
      double bytes = 0;
      cpu0 = process_cpu_seconds();
      const auto t0 = Clock::now();
      for (int k = 0; k < n; ++k) {
        const fs::path p = dir / "f.png";
        write_png(p, frame_at(frames, k), opt);
        bytes += double(fs::file_size(p));
      }
      row("PNG level " + std::to_string(opt.compression_level) + (opt.filters ? ", filters" : ", no filters"),
          seconds_since(t0), n, bytes);
    }
  }

  // MP4 per preset (crf 20, 2 encoder threads, 30 fps)
  for (const std::string& preset : presets) {
    Mp4Options o;
    o.preset = preset;
    const fs::path p = dir / (preset + ".mp4");
    cpu0 = process_cpu_seconds();
    const auto t0 = Clock::now();
    double finish_s = 0;
    {
      Mp4Sink sink(p, o);
      for (int k = 0; k < mp4_frames; ++k) sink.consume(frame_at(frames, k), k, k / 30.0);
      const auto tf = Clock::now();
      sink.finish();
      finish_s = seconds_since(tf);
    }
    row("MP4 x264 " + preset + " crf 20", seconds_since(t0), mp4_frames, double(fs::file_size(p)), finish_s);
    if (mp4_only) std::printf("%-40s %ju bytes\n", "", static_cast<std::uintmax_t>(fs::file_size(p)));
  }
  if (mp4_only) return 0;

  // Overlap: a producer spending `work` seconds per frame feeds PNG (level 1) + MP4 (default
  // preset), inline versus through AsyncSink. "busy" burns CPU like the simulation does (on a
  // loaded 2-core machine there may be no idle core to overlap with); "sleep" waits like a
  // GPU read-back would, which isolates the overlap itself from CPU contention.
  const double work = 0.030;
  for (const bool sleeping : {false, true})
    for (const bool async : {false, true}) {
      fs::remove_all(dir / "frames");
      std::vector<std::unique_ptr<FrameSink>> sinks;
      sinks.push_back(std::make_unique<PngSequenceSink>(dir / "frames"));
      sinks.push_back(std::make_unique<Mp4Sink>(dir / "run.mp4"));
      std::unique_ptr<AsyncSink> as;
      if (async) as = std::make_unique<AsyncSink>(std::move(sinks), 4);
      const int n = mp4_frames;
      cpu0 = process_cpu_seconds();
      const auto t0 = Clock::now();
      for (int k = 0; k < n; ++k) {
        if (sleeping)
          std::this_thread::sleep_for(std::chrono::duration<double>(work));
        else
          busy(work);
        if (as)
          as->consume(frame_at(frames, k), k, k / 30.0);
        else
          for (auto& s : sinks) s->consume(frame_at(frames, k), k, k / 30.0);
      }
      if (as)
        as->finish();
      else
        for (auto& s : sinks) s->finish();
      const double sec = seconds_since(t0);
      row(std::string(async ? "async" : "inline") + (sleeping ? ", 30 ms sleep" : ", 30 ms busy") +
              " + PNG1 + MP4",
          sec, n, 0.0);
      if (as) std::printf("%-40s %10.1f s blocked in consume()\n", "", as->blocked_seconds());
    }
  std::printf("\n(producer-only bound: %.1f frames/s; machine: %u hardware threads)\n", 1.0 / work,
              std::thread::hardware_concurrency());
  return 0;
}
