// What the renderer draws: particles (position, radius, a colour attribute), the domain
// and obstacles, binned fields (seed 003 §4.1: density, kT, velocity on one grid) and
// labels. Built by the scene layer from engine state or from particle files; the renderer
// knows nothing about physics.
#pragma once
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "engine/core/field_grid.hpp"

namespace grainflow::render {

struct Circle {
  Eigen::Vector2d centre{0, 0};
  double radius = 0;
};

// A named scalar field: `name` is what panels ask for ("density", "temperature",
// "speed", …); `label` is the colour-bar label (e.g. "kT"), the name when empty.
// A boundary plane across a 2D domain (the dispenser piston, the outlet filter): drawn as
// a line on every panel, so that the reader sees where the stream is fed and let out.
struct BoundaryLine {
  Eigen::Vector2d a{0, 0}, b{0, 0};
};

struct NamedField {
  std::string name;
  std::string label;
  core::ScalarField field;
};

// Where a Snapshot's binned fields come from, for files of them (output.fields): the
// exposure they average over and the plane of the box their grid lies in.
struct FieldExposure {
  double t_begin = 0, t_end = 0;  // the exposure window [t_begin, t_end]
  int samples = 0;                // snapshots of the particles binned over it
  std::array<int, 2> axes{0, 1};  // the box axes (0 x, 1 y, 2 z) of the grid's u and v
  // 3D: the coordinates across the plane the bins average over; unset: the whole box.
  std::optional<std::array<double, 2>> slab;
};

struct Snapshot {
  int dim = 2;                        // 2: disks in the x–y plane; 3: spheres
  Eigen::Vector3d lo{0, 0, 0};        // domain box
  Eigen::Vector3d hi{1, 1, 1};
  // Periodic axes of the box: a 2D disk across a periodic edge is drawn on both sides,
  // clipped to the box (particle files mark the axes pbc="T").
  std::array<bool, 3> periodic{false, false, false};
  // 3D: faces with neither a wall nor a periodic image (x lo, x hi, y lo, y hi, z lo, z hi;
  // DEM boundary.top = "open"). Every other face of a non-periodic axis is a wall.
  std::array<bool, 6> open_faces{};
  std::vector<float> pos_radius;      // x, y, z, radius per particle (world units)
  std::vector<float> attribute;       // raw colour attribute per particle, or empty
  std::string attribute_name;         // e.g. "speed", "type" — for labels
  bool attribute_categorical = false; // integer categories (species, type)
  // Names of categories for the legend: category_names[k − 1] names category k (species
  // of an XYZ file); empty: "type k".
  std::vector<std::string> category_names;
  std::vector<Circle> obstacles;      // 2D solid circles drawn on top
  std::vector<BoundaryLine> boundary_lines;  // 2D planes drawn on top (piston, filter)
  double time = 0;
  std::string time_unit;              // for the caption ("s", "τ"); with length_unit, the flow-speed bar's unit
  std::string length_unit;            // for the scale bars ("σ", "m"); empty when unknown

  // Binned fields. All fields, scalar and vector, lie on the same GridGeometry; a bin with
  // mask 0 (empty, solid) or a NaN/inf value is drawn in Colormap::kNanColour.
  std::vector<NamedField> fields;
  std::optional<core::VectorField> velocity;
  // The stream velocity U: streamline panels may draw the flow relative to it.
  std::optional<Eigen::Vector2d> reference_velocity;
  // Set with the fields by a run (not by `grainflow render`): the exposure that made them.
  std::optional<FieldExposure> exposure;
  // Set by a run whose fields do not exist yet (the first exposure is not over): what a
  // field panel says instead of "no density field" (e.g. "fields from t = 8").
  std::string fields_pending;
  // Caption line under the panels: `caption` when set, else "key = value" pairs joined
  // (e.g. {"t", "120"}, {"U", "0.1"}, {"Re", "40"}, {"τ_E", "480"}, {"N", "160000"}).
  std::string caption;
  std::vector<std::pair<std::string, std::string>> labels;

  std::size_t size() const { return pos_radius.size() / 4; }
  // The scalar field called `name`, or nullptr.
  const NamedField* field(std::string_view name) const {
    for (const auto& f : fields)
      if (f.name == name) return &f;
    return nullptr;
  }
};

}  // namespace grainflow::render
