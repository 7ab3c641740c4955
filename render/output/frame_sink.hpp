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
};

}  // namespace grainflow::render
