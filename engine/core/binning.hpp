// Binned fields of a particle system on a regular grid over a plane (seed 003 §4.1):
// number density, area/solid fraction, mean velocity, granular temperature kT from the
// peculiar velocities (Eq. 4.9: (i/2) kT = (1/2) m <C²>, i = 2 in 2D, 3 in 3D) and mean
// speed, for one frame or time-averaged over an exposure τ_E (BinAccumulator).
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "engine/core/field_grid.hpp"
#include "engine/core/particle_frame.hpp"
#include "engine/core/vec.hpp"

namespace grainflow::core {

// The plane the grid lies in; its first axis is the grid's x, the second its y, and 3D
// particles are averaged over the third axis (the slab).
enum class BinPlane { xy, xz, yz };

struct BinningOptions {
  GridGeometry grid;
  BinPlane plane = BinPlane::xy;
  // 3D only: keep particles whose coordinate along the third axis lies in
  // [slab_lo, slab_hi). Unset: every particle, and the slab thickness (needed for the
  // solid fraction) is the box extent along that axis of each added frame.
  std::optional<double> slab_lo, slab_hi;
};

// Sums over particles and frames. A particle is counted in the bin holding its centre
// (no partial overlap), so fractions are estimates that need bins several diameters wide.
// Averages over an exposure weight every particle-sample equally, as the seed's time
// average of bin samples does: <v> = Σ m v / Σ m, kT = (Σ m|v|² − |<v>|² Σ m) / (i N),
// with N the number of particle-samples in the bin (no N/(N−1) correction).
class BinAccumulator {
public:
  explicit BinAccumulator(const BinningOptions& options);

  // One frame. Particles outside the grid or the slab are not binned (see outside()).
  // Masses come from an extra column "mass" when the frame has one, else 1.
  void add(const ParticleFrame& frame);
  // One frame from arrays (the engines' samplers). radius and mass may be empty (then no
  // fraction / unit mass); velocity may be empty (then no velocity fields).
  void add(std::span<const Vec2> position, std::span<const Vec2> velocity, std::span<const double> radius = {},
           std::span<const double> mass = {});
  void add(std::span<const Vec3> position, std::span<const Vec3> velocity, std::span<const double> radius = {},
           std::span<const double> mass = {}, double slab_thickness = 0.0);

  // Particle by particle, then end_frame(): for engines that do not store arrays.
  // dim 2 particles have z = 0 and vz = 0. slab_thickness is used in 3D only (0: unknown).
  void begin_frame(int dim, bool with_velocity, bool with_radius, double slab_thickness = 0.0);
  void deposit(const Vec3& position, const Vec3& velocity, double radius, double mass);
  void end_frame();

  void reset();
  int frames() const { return frames_; }
  int dim() const { return dim_; }
  std::uint64_t outside() const { return outside_; }  // particle-samples not binned
  const BinningOptions& options() const { return opt_; }

  // Mean number of particles per unit bin area (3D: projected on the plane). Empty bins
  // hold 0 and stay valid: zero particles is a measurement, not a missing value.
  ScalarField density() const;
  // 2D: area fraction Σπr² / bin area. 3D: solid fraction Σ(4/3)πr³ / (bin area × slab
  // thickness). Empty bins hold 0. Throws grainflow::Error when radii (or, in 3D, the
  // slab thickness) were not given for every frame.
  ScalarField fraction() const;
  // Mass-weighted mean velocity, in-plane components. Empty bins: mask 0, NaN.
  VectorField mean_velocity() const;
  // Granular temperature (Eq. 4.9) with i = dim translational degrees of freedom.
  // Bins with fewer than 2 particle-samples (no fluctuation to measure): mask 0, NaN.
  ScalarField temperature() const;
  // Mean speed <|v|> (all components). Empty bins: mask 0, NaN.
  ScalarField mean_speed() const;
  // Particle-samples per bin.
  std::vector<std::uint64_t> counts() const { return count_; }

  // Everything accumulated so far (for checkpoints: io::save/io::load in
  // engine/io/archive.hpp); set_state takes back what state() gave under the same options.
  struct State {
    int dim = 0, frames = 0;
    bool frame_vel = false, frame_rad = false, all_vel = true, all_rad = true, all_slab = true;
    double slab_sum = 0.0;
    std::uint64_t outside = 0;
    std::vector<std::uint64_t> count;
    std::vector<double> mass, vol, speed, msq;
    std::vector<double> mom;  // 3 per bin
  };
  State state() const;
  void set_state(const State& st);  // throws grainflow::Error when the bin counts differ

private:
  void require_velocity(const char* what) const;
  void check_dim(int dim);

  BinningOptions opt_;
  int axis_u_ = 0, axis_v_ = 1, axis_w_ = 2;
  int dim_ = 0;  // 0 until the first frame
  int frames_ = 0;
  bool frame_vel_ = false, frame_rad_ = false;
  bool all_vel_ = true, all_rad_ = true, all_slab_ = true;
  double slab_sum_ = 0.0;  // Σ over frames of the slab thickness (3D)
  std::uint64_t outside_ = 0;
  std::vector<std::uint64_t> count_;
  std::vector<double> mass_, vol_, speed_, msq_;  // Σm, Σ volume, Σ|v|, Σ m|v|²
  std::vector<Vec3> mom_;                          // Σ m v
};

struct BinnedFields {
  ScalarField density;
  std::optional<ScalarField> fraction;          // when radii are known (3D: and a slab)
  std::optional<VectorField> mean_velocity;     // when velocities are known
  std::optional<ScalarField> temperature;
  std::optional<ScalarField> mean_speed;
  // Particle-samples per bin over the frames binned (the field files' sample counts).
  std::vector<std::uint64_t> counts;
};

// The vorticity of a mean-velocity field about the grid's normal: ω = ∂V/∂u − ∂U/∂v with
// (U, V) the components along the grid's axes (u, v), by central differences between
// valid neighbours (one-sided at an edge or beside a masked bin; masked when neither
// neighbour along an axis is valid). Not periodic: edge bins use one-sided differences.
ScalarField vorticity(const VectorField& velocity);

// The fields of one instantaneous frame.
BinnedFields bin_frame(const ParticleFrame& frame, const BinningOptions& options);

// The plane named "xy", "xz" or "yz"; throws Error naming the allowed names otherwise.
BinPlane bin_plane(std::string_view name);
// The box axes (0 x, 1 y, 2 z) of the plane's grid axes u and v, and the axis across it.
std::array<int, 2> plane_axes(BinPlane plane);
int plane_normal(BinPlane plane);
// A grid of bins[0] × bins[1] bins on `plane` spanning the box [lo, hi] along the plane's
// axes; 3D particles are kept within [slab[0], slab[1]) across the plane when a slab is
// given, else every one (averaged across the whole box). The one set-up of 3D field
// planes, for `grainflow run` (DEM sample.plane/bins/slab) and `grainflow render`
// (--plane/--bins/--slab).
BinningOptions plane_binning(BinPlane plane, const Vec3& lo, const Vec3& hi, std::array<int, 2> bins,
                             std::optional<std::array<double, 2>> slab = std::nullopt);
// Bins per axis of a rectangle of `extent` such that no bin is narrower than `min_width`
// (at least one per axis): the default grid of 3D fields, whose bins must hold whole
// particles (a centre is binned, not its volume), so about two diameters wide.
std::array<int, 2> bins_no_finer_than(const Vec2& extent, double min_width);

}  // namespace grainflow::core
