// The extension point for where rendered frames go (ARCHITECTURE.md, "Data flow"): a PNG
// sequence, an MP4, an asynchronous wrapper around either. Sinks are independent; a run
// holds any number of them.
#pragma once
#include <cstdint>

#include "render/image/image.hpp"

namespace grainflow::render {

class FrameSink {
public:
  virtual ~FrameSink() = default;
  // Takes one frame. `index` counts frames from 0 in the order given; `time` is the
  // simulated time the frame shows. Throws grainflow::Error on I/O failure.
  virtual void consume(const Image& frame, std::int64_t index, double time) = 0;
  // Completes every output (flushes encoders, renames files into place). A sink destroyed
  // without finish() leaves no file under a finished-looking name.
  virtual void finish() = 0;
  // For checkpoints (`grainflow run --resume`): returns once every frame consumed so far is
  // in the output's files (handed to the kernel; nothing is fsync'ed) and the files hold
  // them as a prefix that a run resumed at this frame count continues. An MP4 drains its
  // encoder (Mp4Writer::sync()); an asynchronous sink waits for its queue. Throws
  // grainflow::Error on I/O failure (or the failure an asynchronous sink met earlier).
  // Default: nothing to do, for sinks whose every frame is complete when consume() returns.
  virtual void sync() {}
};

}  // namespace grainflow::render
