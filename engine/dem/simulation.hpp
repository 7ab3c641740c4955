// The 3D soft-sphere DEM engine (seed 000 ch. 2–5): Walton / Hooke contacts with history,
// leap-frog integration (Eq. 2.19), Verlet table built by chain cells, box walls or
// periodic axes, two particle groups, van der Waals cohesion; the pressure tensor of the
// motion and the contact virial (Stats).
// UNITS: SI throughout — metres, kilograms, seconds, newtons, joules, radians per second.
#pragma once
#include <array>
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

#include "engine/core/vec.hpp"
#include "engine/dem/contact_law.hpp"
#include "engine/dem/contact_params.hpp"
#include "engine/dem/neighbor_list.hpp"
#include "engine/dem/particle_state.hpp"
#include "engine/dem/thread_sync.hpp"

namespace grainflow::io {
class ArchiveWriter;
class ArchiveReader;
}  // namespace grainflow::io

namespace grainflow::dem {

struct GroupConfig {
  double radius = 0.5e-3;    // [m]
  double density = 2500.0;   // [kg/m³]
  ContactParams contact;     // particle–particle within the group and particle–wall
};

struct BoxConfig {
  Vec3 lo{0.0, 0.0, 0.0};
  Vec3 hi{0.01, 0.01, 0.01};
  std::array<bool, 3> periodic{false, false, false};
  bool open_top = false;  // no wall at z = hi
  // Velocity of each wall (0: x lo, 1: x hi, 2: y lo, 3: y hi, 4: z lo, 5: z hi) [m/s];
  // only the in-plane components are allowed (plane Couette), the walls do not move normally.
  std::array<Vec3, 6> wall_velocity{Vec3::Zero(), Vec3::Zero(), Vec3::Zero(),
                                    Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
};

struct ParticleInit {
  Vec3 x = Vec3::Zero();
  Vec3 v = Vec3::Zero();
  Vec3 omega = Vec3::Zero();
  int group = 0;
  double radius = 0.0;  // 0: the group's radius
};

struct Config {
  BoxConfig box;
  std::vector<GroupConfig> groups{GroupConfig{}};  // one or two groups
  std::optional<ContactParams> mixed_contact;       // group 0–1 pairs; default: mix()
  ContactModelSpec model;
  Vec3 gravity{0.0, 0.0, -9.81};
  double dt = 0.0;               // 0: Eq. 2.23 with steps_per_collision
  int steps_per_collision = 50;  // n of Eq. 2.23
  double skin = -1.0;            // Verlet search distance beyond contact [m]; < 0: 0.2 × largest diameter
  NeighborMethod neighbor = NeighborMethod::ChainCells;
  // Radius growth (seed 000 §2.1, FINDRAD): radii start at growth_start × final radius and
  // grow linearly to the final radius over growth_steps steps while the contact forces
  // push the particles apart (masses are those of the final radii throughout).
  // growth_steps = 0: no growth. Overlap checks at set-up use the starting radii.
  double growth_start = 1.0;
  std::uint64_t growth_steps = 0;
  std::vector<ParticleInit> particles;
};

struct Stats {
  double time = 0.0;
  std::uint64_t step = 0;
  double kinetic = 0.0;         // Σ ½ m v² at the full step [J]
  double rotational = 0.0;      // Σ ½ I ω² [J]
  double potential_gravity = 0.0;  // Σ −m g·x [J]
  std::size_t contacts = 0;     // particle–particle pairs with overlap > 0
  std::size_t wall_contacts = 0;
  double coordination = 0.0;    // 2 × contacts / N
  std::array<Vec3, 6> wall_force{};  // force exerted by the particles on each wall [N]
  // Pressure tensor [Pa] at the current step, components xx, yy, zz, xy, xz, yz:
  //   P_ab = (Σ_i m_i C_a C_b + W_ab) / V,  C = v_i − V_cm,
  // v_i the full-step velocity (as in `kinetic`), V_cm = Σ m v / Σ m the mass-averaged
  // velocity, V = the box volume (lx ly lz, open top included), and W the contact virial:
  //   W_ab = Σ_pairs r_ij,a F_ij,b + Σ_wall contacts r_a F_b (symmetrised off the diagonal),
  // r_ij = x_i − x_j the periodic image the force acts across, F_ij the force on i; for a
  // wall contact r = x_i − its foot on the wall plane. With the wall contacts, W/V is
  // the Love–Weber mean stress (sign reversed) of all particles, each summing its contact
  // forces times the branch vectors from its centre: particles pressed only against a
  // wall carry stress too. Gravity acts at the centres (branch vector 0) and does not
  // enter, as LAMMPS's fix gravity adds no virial; a bed at rest whose weight the floor
  // alone carries has W_zz = Σ m |g| (z_i − z_lo). pressure = (P_xx + P_yy + P_zz)/3.
  std::array<double, 6> pressure_tensor{};
  double pressure = 0.0;
  std::array<double, 6> virial_pairs{}, virial_walls{};  // W split [J]
  double volume = 0.0;  // [m³]
  std::uint64_t neighbor_builds = 0;
  std::size_t neighbor_pairs = 0;
};

class Simulation {
public:
  // Validates the configuration; throws grainflow::Error naming the offending key/value.
  explicit Simulation(Config cfg);
  ~Simulation();
  Simulation(Simulation&&) noexcept;
  Simulation& operator=(Simulation&&) noexcept;

  void step(std::uint64_t n = 1);

  double time() const { return time_; }
  std::uint64_t steps() const { return step_; }
  double dt() const { return dt_; }
  // Largest stable time step of this configuration (leap-frog, stiffest spring, lightest pair).
  double dt_limit() const { return dt_limit_; }
  std::size_t size() const { return p_.n; }
  const Config& config() const { return cfg_; }

  // State access. Positions are those of the current step; velocities are reported at the
  // full step (v_n = v_{n−1/2} + ½Δt F_n/m, Eq. 2.19); forces are always those at the
  // current positions (computed at the end of each step, as LAMMPS does).
  Vec3 position(std::size_t i) const { return {p_.x[3 * i], p_.x[3 * i + 1], p_.x[3 * i + 2]}; }
  double radius(std::size_t i) const { return p_.radius[i]; }
  double mass(std::size_t i) const { return p_.mass[i]; }
  int group(std::size_t i) const { return p_.group[i]; }
  Vec3 velocity(std::size_t i) const;
  Vec3 angular_velocity(std::size_t i) const;
  Vec3 force(std::size_t i) const;   // total force at the current positions [N]
  Vec3 torque(std::size_t i) const;
  const Particles& particles() const { return p_; }     // raw arrays (v, w at the half step)
  const NeighborList& neighbors() const { return list_; }
  // Squared centre distance of table entry q of particle i (periodic shift applied): the
  // one contact test of the engine, its stats and its packing measures.
  double centre_distance_sq(std::size_t i, std::uint32_t q) const;
  const ContactLaw& contact_law() const { return *law_; }
  Stats stats() const;
  // Stats::pressure_tensor alone (no contact count): O(N) [Pa].
  std::array<double, 6> pressure_tensor() const;

  // Checkpoint state (checkpoint.cpp): the full state incl. contact history and the
  // neighbour table. load_state restores it into a Simulation built from the same Config
  // (any thread count), which then continues bit for bit; throws grainflow::Error when the
  // archive was saved under another configuration or is truncated or corrupt.
  void save_state(io::ArchiveWriter& w) const;
  void load_state(io::ArchiveReader& r);

private:
  void setup();
  void configure();        // contact law, time step, box
  void place_particles();  // validated initial state, first neighbour table
  void rebuild();
  void integrate();  // leap-frog kick + drift, displacement check
  // F_n at the current positions (history updated if asked), optionally fused with the
  // next kick + drift.
  void compute_forces(bool update, bool then_integrate);
  // compute_forces in three parts, so that a parallel region can span several steps:
  // serial set-up, the share of thread t of T (every thread of the team calls it), serial
  // end (wall forces, displacement check).
  std::size_t force_chunks() const;
  void begin_force_pass(bool update, bool then_integrate);
  void force_pass_share(std::size_t t, std::size_t T);
  void end_force_pass();
  void finish_integrate();
  void update_wall_near();
  void grow_radii();  // FINDRAD step
  Config cfg_;
  Particles p_;
  Box box_;
  NeighborList list_;
  std::unique_ptr<ContactLaw> law_;
  std::vector<double> wall_hist_;
  std::vector<std::uint8_t> wall_flags_;
  std::vector<std::uint32_t> wall_first_, wall_slot_;  // ForcePass::wall_*, rebuilt with the table
  std::vector<double> final_radius_;     // radius growth target
  std::vector<double> chunk_wall_;   // per chunk 6×3
  std::vector<double> chunk_disp_;   // per chunk max squared displacement
  // Per chunk: the virial of its pairs (6) and of its wall contacts (6), summed over the
  // chunks in ascending order at the end of the pass: the same bits for any thread count.
  std::vector<double> chunk_virial_;
  std::unique_ptr<ThreadSync> sync_;  // chunk flags and barrier of the force passes
  // Per chunk: smoothed seconds of its force work, and the last pass's of its pair pass
  // and rest, from which more than two threads divide the chunks into segments (timing
  // only moves work between threads, never changes a result).
  std::vector<double> chunk_cost_, chunk_time_;
  struct PassPlan {
    bool update = true, integrate = false;
    bool virial = false;  // the last pass of a step() batch: its forces are the state's
    double kick = 0.0;
    std::uint32_t number = 0;
    std::size_t team = 1;  // threads that took part
  } pass_;
  std::uint32_t force_passes_ = 0;
  double dt_ = 0.0, dt_limit_ = 0.0, skin_ = 0.0, time_ = 0.0;
  std::uint64_t step_ = 0;
  bool started_ = false;         // first kick is a half kick (v given at t = 0)
  bool need_rebuild_ = false;
  std::array<Vec3, 6> wall_force_{};
  // The contact virial of the forces now in p_.f (see Stats::pressure_tensor), measured by
  // the pass that computed them: pairs and walls.
  std::array<double, 6> virial_pairs_{}, virial_walls_{};
};

// Threads the force passes use: OMP_NUM_THREADS or all cores unless set (1 without
// OpenMP). Results do not depend on it.
int thread_count();
void set_thread_count(int n);

// Initial positions (seed 000 §2.1: lattice, random, or read from a list).
// Simple cubic lattice with spacing a, first site at lo + a/2 per axis, x fastest.
std::vector<Vec3> simple_cubic_lattice(const Vec3& lo, double spacing, int nx, int ny, int nz);
// Random non-overlapping centres (random sequential addition with the run's seeded Rng);
// throws grainflow::Error when `count` spheres of radius r do not fit after many tries.
std::vector<Vec3> random_positions(const Vec3& lo, const Vec3& hi, double r, std::size_t count,
                                   std::uint64_t seed);

}  // namespace grainflow::dem
