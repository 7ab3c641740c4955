// What the renderer draws: particles (position, radius, a colour attribute), the domain
// and obstacles, and labels. Built by the scene layer from engine state or from particle
// files; the renderer knows nothing about physics.
#pragma once
#include <string>
#include <vector>

#include <Eigen/Core>

namespace grainflow::render {

struct Circle {
  Eigen::Vector2d centre{0, 0};
  double radius = 0;
};

struct Snapshot {
  int dim = 2;                        // 2: disks in the x–y plane; 3: spheres
  Eigen::Vector3d lo{0, 0, 0};        // domain box
  Eigen::Vector3d hi{1, 1, 1};
  std::vector<float> pos_radius;      // x, y, z, radius per particle (world units)
  std::vector<float> attribute;       // raw colour attribute per particle, or empty
  std::string attribute_name;         // e.g. "speed", "type" — for labels
  bool attribute_categorical = false; // integer categories (species, type)
  std::vector<Circle> obstacles;      // 2D solid circles drawn on top
  double time = 0;

  std::size_t size() const { return pos_radius.size() / 4; }
};

}  // namespace grainflow::render
