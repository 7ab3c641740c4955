// Scalar field maps (SPEC §3 "scalar field maps"; seed 003 §4.1, Fig. 4.2–4.22): a binned
// field drawn as a colour-mapped texture over its grid rectangle, nearest or bilinear,
// with masked and non-finite bins in the neutral Colormap::kNanColour, and the colour range
// fixed, automatic, or from percentiles so that one hot bin does not wash the map out.
#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "engine/core/field_grid.hpp"
#include "render/context/shader_program.hpp"
#include "render/layers/camera.hpp"
#include "render/layers/colormap.hpp"
#include "render/layers/gl_buffer.hpp"
#include "render/layers/streamlines.hpp"

namespace grainflow::render {

struct FieldRange {
  enum class Mode { automatic, fixed, percentile };
  Mode mode = Mode::automatic;
  double lo = 0.0, hi = 1.0;                    // Mode::fixed
  double lo_percent = 2.0, hi_percent = 98.0;  // Mode::percentile, 0 ≤ lo < hi ≤ 100
  // Signed fields (vorticity) on a diverging map: the automatic or percentile range is
  // widened to [−m, m], m the larger end, so that 0 is the map's neutral centre.
  bool symmetric = false;

  static FieldRange fixed(double lo, double hi) { return {Mode::fixed, lo, hi}; }
  static FieldRange percentile(double lo_percent, double hi_percent) {
    return {Mode::percentile, 0.0, 1.0, lo_percent, hi_percent};
  }
};

// The colour range of a field's valid, finite bins. Never empty: a constant field c gets
// [c − 0.05|c|, c + 0.05|c|] ([c − 0.5, c + 0.5] for c = 0), a field without valid bins
// {0, 1}. Percentiles interpolate linearly between order statistics. Throws
// grainflow::Error for a fixed range with hi ≤ lo or non-finite ends, or bad percentiles.
std::pair<double, double> resolve_range(const core::ScalarField& field, const FieldRange& range);
// Same for plain values (NaN/inf ignored).
std::pair<double, double> resolve_range(const std::vector<double>& values, const FieldRange& range);

enum class FieldFilter { nearest, bilinear };

// The bins under a solid circle (the obstacle, drawn over the map): a bin whose centre it
// covers holds no gas and is masked, but its square's corners poke out of the round
// obstacle. Each masked (valid[b] = 0) bin whose square reaches into a circle takes the
// mean of its valid 8 neighbours, in passes (each from the previous pass's bins) until
// none is left that has one; it is then drawn as valid. The map so meets the obstacle's
// edge instead of showing grey square teeth around it. Masked bins away from the solids
// (no data) keep their mask. `values` and `valid` are per bin (grid.index order).
void fill_bins_under_solids(const core::GridGeometry& grid, std::vector<float>& values, std::vector<std::uint8_t>& valid,
                            std::span<const SolidCircle> solids);

class FieldMapLayer {
public:
  explicit FieldMapLayer(const GlApi& gl);

  // Draws `field` over its grid rectangle; value v maps to t = (v − lo)/(hi − lo), clamped.
  // Masked bins under the `solids` (drawn over the map afterwards) are filled from their
  // neighbours (fill_bins_under_solids).
  void draw(const ViewTransform& view, const core::ScalarField& field, std::pair<double, double> range,
            const Colormap& colormap, FieldFilter filter = FieldFilter::nearest,
            std::span<const SolidCircle> solids = {});
  // A colour-bar strip: the whole map from t = 0 at lo.y to t = 1 at hi.y (world units of
  // `view`), smooth.
  void draw_gradient(const ViewTransform& view, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
                     const Colormap& colormap);

private:
  void bind_colormap(const Colormap& colormap);
  void draw_texels(const ViewTransform& view, int nx, int ny, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
                   bool bilinear);

  const GlApi& gl_;
  ShaderProgram program_;
  GlVertexArray vao_;
  GlTexture field_texture_, colormap_texture_;
  std::optional<ColormapId> uploaded_map_;
  std::vector<float> texels_;  // RG per bin, reused
  std::vector<float> values_;  // per bin, reused
  std::vector<std::uint8_t> valid_;
};

}  // namespace grainflow::render
