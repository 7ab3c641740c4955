// A CPU rasteriser for many small 2D disks, used on software GL (llvmpipe). There, every
// point sprite costs ~1–3 µs of single-threaded vertex and set-up work, so 1.6×10^5 disks
// cannot reach 10 frames/s; splatting them here and drawing the result as one textured
// quad is an order of magnitude faster. The pixels match the sprite shaders
// (assets/shaders/disks.*): same coverage, rim and colours, composited in particle order.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "render/layers/camera.hpp"
#include "render/layers/colormap.hpp"

namespace grainflow::render {

class DiskSplatter {
public:
  // Rasterises disks into a premultiplied RGBA8 image of width × height, row 0 at the
  // bottom (GL's order, so it uploads as a texture unchanged). values: colour coordinate
  // in [0, 1] per disk or empty (flat colour); colours come from `texels`, the same
  // table the sprite path samples, with GL's linear filtering between texel centres.
  void splat(const ViewTransform& view, int width, int height, std::span<const float> pos_radius,
             std::span<const float> values, const std::vector<Rgba8>& texels, bool categorical, Rgba8 flat,
             Rgba8 nan_colour);

  const std::vector<std::uint8_t>& pixels() const { return pixels_; }

private:
  std::vector<std::uint8_t> pixels_;
};

}  // namespace grainflow::render
