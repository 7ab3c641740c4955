// The MP4's frame-rate key, shared by its output (image_outputs.cpp) and the run loop,
// which picks a rate when the scene gives none (run/run_loop.hpp: auto_fps_override).
#pragma once
#include <cstdint>

#include "scenes/src/scene/schema.hpp"

namespace grainflow::scenes::video_keys {
inline constexpr Key<std::int64_t> fps{"output.fps"};
}  // namespace grainflow::scenes::video_keys
