// Rectangles in frame pixels (top-left origin, y down: the order of Image rows) and the
// view that draws in those coordinates: panel areas, colour bars, overlays.
#pragma once
#include "render/layers/camera.hpp"

namespace grainflow::render {

struct PixelRect {
  int x = 0, y = 0, w = 0, h = 0;
  int right() const { return x + w; }
  int bottom() const { return y + h; }
};

// World coordinates = frame pixels (x right, y down) over a width × height viewport.
inline ViewTransform pixel_view(int width, int height) {
  ViewTransform v;
  v.proj = Mat4::Identity();
  v.proj(0, 0) = 2.0f / float(width);
  v.proj(0, 3) = -1.0f;
  v.proj(1, 1) = -2.0f / float(height);
  v.proj(1, 3) = 1.0f;
  v.pixels_per_unit = 1.0f;
  return v;
}

}  // namespace grainflow::render
