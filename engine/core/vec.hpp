// Fixed-size vector types used across grainflow (engines, samplers, renderer input).
// Eigen fixed-size types: no heap, vectorised, and one spelling for the whole project.
#pragma once
#include <Eigen/Core>

namespace grainflow {
using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Vec2f = Eigen::Vector2f;
using Vec3f = Eigen::Vector3f;
}  // namespace grainflow
