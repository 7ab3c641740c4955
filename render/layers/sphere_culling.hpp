// Conservative occlusion culling of sphere impostors on the CPU, for software GL. There,
// every fragment of every sphere sprite is ray-cast (the shader writes depth, so no early
// depth test), and in a dense 3D packing most spheres are hidden behind the outer
// layers. Spheres are taken front to back; a per-pixel buffer keeps the depth behind
// which a sphere already kept covers the pixel; a sphere whose nearest point lies behind
// that depth in every pixel its outline touches cannot show, and is dropped. The picture is unchanged (tests compare with and without culling).
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "render/layers/camera.hpp"

namespace grainflow::render {

class SphereCuller {
public:
  // Indices of the spheres that may be visible, front to back. pos_radius: x, y, z, r.
  const std::vector<std::uint32_t>& visible(const ViewTransform& view, int width, int height,
                                            std::span<const float> pos_radius);

private:
  struct Item {
    float near_depth;  // distance of the sphere's nearest point in front of the eye
    std::uint32_t index;
  };
  std::vector<Item> items_;
  std::vector<float> tiles_;  // per pixel: depth behind which the pixel is covered
  std::vector<std::uint32_t> visible_;
};

}  // namespace grainflow::render
