// A regular 2D grid of binned values (nx × ny bins over a rectangle) shared by both
// engines' samplers and the renderer: scalars (density, kT, |v|) and 2-vectors (mean
// velocity), with a mask for bins that hold no data (empty, or inside a solid obstacle).
// Seed 003 §4.1: fields are binned and time-averaged over an exposure τ_E.
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/core/vec.hpp"

namespace grainflow::core {

struct GridGeometry {
  int nx = 60, ny = 60;
  Vec2 lo{0.0, 0.0};  // lower-left corner of bin (0, 0)
  Vec2 hi{1.0, 1.0};  // upper-right corner of bin (nx-1, ny-1)

  double dx() const { return (hi.x() - lo.x()) / nx; }
  double dy() const { return (hi.y() - lo.y()) / ny; }
  std::size_t size() const { return static_cast<std::size_t>(nx) * ny; }
  std::size_t index(int ix, int iy) const { return static_cast<std::size_t>(iy) * nx + ix; }
  Vec2 centre(int ix, int iy) const { return {lo.x() + (ix + 0.5) * dx(), lo.y() + (iy + 0.5) * dy()}; }
  // Bin containing p, or false when p is outside the rectangle.
  bool bin_of(const Vec2& p, int& ix, int& iy) const {
    const double fx = (p.x() - lo.x()) / dx(), fy = (p.y() - lo.y()) / dy();
    if (!(fx >= 0.0 && fy >= 0.0 && fx < nx && fy < ny)) return false;
    ix = static_cast<int>(fx);
    iy = static_cast<int>(fy);
    return true;
  }
};

// Values live at bin centres. mask[i] == 0 marks a bin without data; readers must treat
// its value as undefined (it may be NaN).
// Zero of a value type: T{} leaves Eigen vectors uninitialised.
template <class T>
T zero_value() {
  if constexpr (requires { T::Zero(); }) return T::Zero();
  else return T{};
}

template <class T>
struct Field {
  GridGeometry grid;
  std::vector<T> values;
  std::vector<std::uint8_t> mask;  // 1 = valid, 0 = empty or solid

  Field() = default;
  explicit Field(const GridGeometry& g, T init = zero_value<T>())
      : grid(g), values(g.size(), init), mask(g.size(), 1) {}

  T& at(int ix, int iy) { return values[grid.index(ix, iy)]; }
  const T& at(int ix, int iy) const { return values[grid.index(ix, iy)]; }
  bool valid(int ix, int iy) const { return mask[grid.index(ix, iy)] != 0; }
};

using ScalarField = Field<double>;
using VectorField = Field<Vec2>;

}  // namespace grainflow::core
