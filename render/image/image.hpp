// An 8-bit RGBA image in memory, top row first (the order of PNG files and video frames;
// the GL read-back is flipped into this order once, in the context layer).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace grainflow::render {

struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;  // width * height * 4 bytes, row-major, top row first

  Image() = default;
  Image(int w, int h) : width(w), height(h), rgba(static_cast<std::size_t>(w) * h * 4, 0) {}

  std::uint8_t* pixel(int x, int y) { return rgba.data() + (static_cast<std::size_t>(y) * width + x) * 4; }
  const std::uint8_t* pixel(int x, int y) const {
    return rgba.data() + (static_cast<std::size_t>(y) * width + x) * 4;
  }
  bool empty() const { return width <= 0 || height <= 0; }
};

}  // namespace grainflow::render
