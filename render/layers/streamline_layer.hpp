// Draws the streamlines of a binned 2D velocity field (render/layers/streamlines.*) as one
// batch of thick anti-aliased segments: coloured by speed or in one colour, with
// arrowheads and/or a tapered width to show direction, optionally relative to the stream
// velocity U (eddies in the co-moving frame), or as plain arrows (quiver). Seed 003 §4.1–4.3.
#pragma once
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "render/layers/camera.hpp"
#include "render/layers/colormap.hpp"
#include "render/layers/segment_layer.hpp"
#include "render/layers/streamlines.hpp"

namespace grainflow::render {

struct StreamlineStyle {
  bool quiver = false;             // plain arrows on every quiver_stride-th bin instead of lines
  int quiver_stride = 0;           // 0: about 20 arrows across the larger grid axis
  bool colour_by_speed = false;    // else line_colour
  Rgb line_colour{1.0f, 1.0f, 1.0f};
  float alpha = 0.9f;
  Colormap colormap{ColormapId::viridis};
  std::optional<std::pair<double, double>> speed_range;  // colour range; default [0, max]
  float width_px = 1.4f;
  // Width grows from taper_start × width at the upstream end to the full width downstream.
  bool taper = false;
  float taper_start = 0.3f;
  bool arrowheads = true;
  float arrow_px = 6.0f;           // arrowhead (chevron) length
  double arrow_spacing = 0.0;      // along each line, domain units; 0: 10 × d_sep
  bool relative_to_reference = false;  // subtract Snapshot::reference_velocity
  StreamlineOptions trace;         // separation etc.; its reference_velocity is set from above
};

class StreamlineLayer {
public:
  explicit StreamlineLayer(const GlApi& gl) : segments_(gl) {}

  // Traces (or, for quiver, samples) the field and appends world-coordinate segments to
  // `out`; pixels_per_unit converts pixel sizes (arrowheads) into world lengths. Returns
  // the speed range used for colour (for a colour bar).
  std::pair<double, double> build(const core::VectorField& field, std::span<const SolidCircle> solids,
                                  const StreamlineStyle& style, const Vec2& reference, float pixels_per_unit,
                                  std::vector<Segment>& out);
  // build() then one instanced draw.
  std::pair<double, double> draw(const ViewTransform& view, int width, int height, const core::VectorField& field,
                                 std::span<const SolidCircle> solids, const StreamlineStyle& style,
                                 const Vec2& reference);

  std::size_t last_line_count() const { return lines_.size(); }

private:
  SegmentLayer segments_;
  std::vector<Streamline> lines_;
  std::vector<Segment> batch_;
};

}  // namespace grainflow::render
