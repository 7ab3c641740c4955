// Streamline geometry for a binned 2D velocity field (pure geometry, no GL): evenly spaced
// streamlines after Jobard & Lefer (1997), arrowheads along them, and a quiver subgrid.
// Seed 003 §4.1–4.3 (Fig. 4.2–4.22): eddies and waving tails of the time-averaged field.
#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "engine/core/field_grid.hpp"
#include "engine/core/vec.hpp"

namespace grainflow::render {

// Solid geometry beyond the field's own mask (the obstacle): streamlines never enter it.
struct SolidCircle {
  Vec2 centre{0.0, 0.0};
  double radius = 0.0;
};

struct StreamlineOptions {
  // Separation d_sep between neighbouring lines, in domain units; 0 means
  // separation_fraction × domain width (x extent). Allowed: 1e-4 … 1 × the domain extent.
  double separation = 0.0;
  double separation_fraction = 0.03;
  // A line stops when it comes closer than d_test = test_fraction × d_sep to another line
  // (or to itself, further than 2·d_test away along its own arc). Guarantee: no vertex of
  // one line is closer than d_test to a vertex of another.
  double test_fraction = 0.5;
  // RK4 step along the arc, in bins (min(dx, dy)); capped at 0.5·d_test so that crossing
  // another line between two vertices cannot go unnoticed.
  double step_bins = 0.25;
  // Total length per line (both directions together: downstream gets half, upstream the
  // rest), domain units; 0 = no limit (lines still end: a line that returns onto itself
  // is stopped or closed, one whose direction turns back within a step stops as at
  // stagnation, and the arc per direction is capped at 8·(W + 2 d_test)(H + 2 d_test)/d_test,
  // above what self-avoidance allows, so the work per line is bounded for any field).
  double max_length = 0.0;
  // Lines shorter than this (domain units) are discarded.
  double min_length = 0.0;
  // Stagnation: stop where |v - reference| < min_speed_fraction × max over the field.
  double min_speed_fraction = 0.02;
  // Subtracted from every bin (e.g. the stream velocity U: eddies in the co-moving frame).
  Vec2 reference_velocity{0.0, 0.0};
  int max_lines = 5000;
  // First seed; default the domain centre. Unusable seeds fall back to a d_sep lattice.
  std::optional<Vec2> seed_start;
};

struct StreamlinePoint {
  Vec2 position;
  double speed = 0.0;       // |v - reference| at the point, for colour
  double arc_length = 0.0;  // from the line's first point, for taper and arrowheads
};

// Oriented along the (relative) flow: points[0] is the most upstream point.
struct Streamline {
  std::vector<StreamlinePoint> points;
  // A loop: the last point equals the first. A line is closed when it returns to its seed
  // within one step along and 5% of d_sep across the flow; a spiral that misses it by more
  // is stopped by the d_test self-proximity test instead.
  bool closed = false;
  double length() const { return points.empty() ? 0.0 : points.back().arc_length; }
};

struct Arrowhead {
  Vec2 position;
  Vec2 direction;  // unit vector along the flow
  double speed = 0.0;
};

struct QuiverArrow {
  Vec2 position;  // bin centre
  Vec2 velocity;  // v - reference
  double speed = 0.0;
};

// Bilinear interpolation of the (relative) velocity between bin centres. A point is
// blocked when it lies outside the rectangle, inside a solid circle, or when one of the
// four bins of its stencil is masked or holds NaN/inf. In the half-bin border the edge
// stencil is extrapolated linearly (exact for linear fields, e.g. solid-body rotation).
class VelocitySampler {
public:
  VelocitySampler(const core::VectorField& field, std::span<const SolidCircle> solids,
                  const Vec2& reference_velocity);

  // Velocity at p into v; false when p is blocked (v untouched).
  bool sample(const Vec2& p, Vec2& v) const;
  bool blocked(const Vec2& p) const;
  bool inside_domain(const Vec2& p) const;
  // Largest |v - reference| over valid, finite bins (0 for an empty field).
  double max_speed() const { return max_speed_; }
  const core::GridGeometry& grid() const { return grid_; }
  // Valid bin (mask set, finite value)?
  bool bin_valid(int ix, int iy) const { return valid_[grid_.index(ix, iy)] != 0; }
  const Vec2& bin_velocity(int ix, int iy) const { return vel_[grid_.index(ix, iy)]; }

private:
  bool in_solid(const Vec2& p) const;
  // Stencil of p: lower-left bin (i0, j0) and weights; false if not usable.
  bool stencil(const Vec2& p, int& i0, int& j0, double& tx, double& ty) const;

  core::GridGeometry grid_;
  std::vector<Vec2> vel_;              // value - reference, zero where invalid
  std::vector<std::uint8_t> valid_;    // per bin
  std::vector<std::uint8_t> cell_ok_;  // per stencil (nx-1)×(ny-1) (or degenerate axes)
  std::vector<SolidCircle> solids_;
  int cx_ = 1, cy_ = 1;                // stencil counts per axis
  double inv_dx_ = 1.0, inv_dy_ = 1.0;
  double max_speed_ = 0.0;
};

// Evenly spaced streamlines (Jobard & Lefer 1997). Deterministic. Throws grainflow::Error
// for invalid options (naming the option, the value and what is allowed).
std::vector<Streamline> trace_streamlines(const core::VectorField& field,
                                          std::span<const SolidCircle> solids,
                                          const StreamlineOptions& options);

// Arrowheads every `spacing` of arc length: max(1, floor(length / spacing)) per line,
// centred on it (a line shorter than `spacing` gets one at its middle).
std::vector<Arrowhead> place_arrowheads(std::span<const Streamline> lines, double spacing);

// Plain arrows on every `stride`-th bin centre (both axes), skipping blocked bins.
std::vector<QuiverArrow> quiver(const core::VectorField& field, std::span<const SolidCircle> solids,
                                const Vec2& reference_velocity, int stride);

}  // namespace grainflow::render
