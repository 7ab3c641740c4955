// The keys of the 2D event-driven hard-disk engine (seed 003 ch. 2–6), declared by
// ed_keys.cpp and read by ed_runner.cpp through these handles. Units: disk diameter
// σ = 1, mass m = 1, energies in kT units.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

#include "scenes/src/scene/schema.hpp"

namespace grainflow::scenes {
class Scene;
}

namespace grainflow::scenes::ed_keys {

inline constexpr Key<std::array<double, 2>> box{"system.box"};
inline constexpr Key<double> area_fraction{"system.area_fraction"};
inline constexpr Key<double> n{"system.n"};
inline constexpr Key<std::int64_t> N{"system.N"};
inline constexpr Key<double> kT{"system.kT"};
inline constexpr Key<double> U{"system.U"};
inline constexpr Key<double> e{"system.e"};
inline constexpr Key<double> e_t{"system.e_t"};
inline constexpr Key<double> mu{"system.mu"};
inline constexpr Key<double> tau_tc{"system.tau_tc"};
inline constexpr Key<double> tau_tc_step{"system.tau_tc_step"};
inline constexpr Key<std::int64_t> collapse_events{"system.collapse_events"};
inline constexpr Key<std::string> calendar{"system.calendar"};
inline constexpr Key<double> cell_size{"system.cell_size"};
inline constexpr Key<std::int64_t> lanes{"system.lanes"};
// The initial state: the melting lattice (at area_fraction | n | N, Maxwell velocities at
// kT plus U), or the disks of a particle file (a run's particles.xyz, an XYZ or LAMMPS dump).
inline constexpr Key<std::string> initial_kind{"system.initial.kind"};
// system.initial.file, frame and ignore: initial_file.hpp, shared with the DEM engine.

inline constexpr Key<std::array<bool, 2>> periodic{"boundary.periodic"};

inline constexpr TableKey obstacle{"boundary.obstacle"};
inline constexpr Key<double> obstacle_D{"boundary.obstacle.D"};
inline constexpr Key<double> obstacle_x{"boundary.obstacle.x"};
inline constexpr Key<double> obstacle_y{"boundary.obstacle.y"};
inline constexpr Key<std::string> obstacle_kind{"boundary.obstacle.kind"};
inline constexpr Key<double> obstacle_r{"boundary.obstacle.r"};

inline constexpr Key<std::string> stream_kind{"boundary.stream.kind"};
inline constexpr Key<double> filter_distance{"boundary.stream.filter_distance"};
inline constexpr Key<std::string> piston{"boundary.stream.piston"};
inline constexpr Key<bool> stream_local_kT{"boundary.stream.local_kT"};

// The box walls' surface and motion (agents/walls.cpp): planar Couette flow (seed 003 §4.2).
inline constexpr TableKey walls{"boundary.walls"};
inline constexpr Key<std::string> walls_kind{"boundary.walls.kind"};
inline constexpr Key<double> walls_r{"boundary.walls.r"};
inline constexpr Key<double> walls_kT{"boundary.walls.kT"};
inline constexpr Key<std::array<double, 2>> walls_U{"boundary.walls.U"};

// The stochastic thermostat of seed 003 ch. 6 (agents/thermostat.cpp).
inline constexpr TableKey thermostat{"thermostat"};
inline constexpr Key<std::string> thermostat_kind{"thermostat.kind"};
inline constexpr Key<double> thermostat_T{"thermostat.T"};
inline constexpr Key<double> thermostat_tau{"thermostat.tau"};
inline constexpr Key<double> thermostat_tau_v{"thermostat.tau_v"};
inline constexpr Key<double> thermostat_bin{"thermostat.bin"};

// Phased runs (agents/phases.cpp): [[phase]] tables, each changing some values at `at`.
inline constexpr TableKey phase{"phase"};
inline constexpr Key<double> phase_at{"phase.at"};
inline constexpr Key<std::string> phase_label{"phase.label"};
inline constexpr Key<double> phase_e{"phase.e"};
inline constexpr Key<double> phase_obstacle_r{"phase.obstacle_r"};
// The obstacle's surface from then on (seed 003 ch. 5: the dune run is elastic with the
// thermal no-slip obstacle first, then inelastic with the random tangential flip).
inline constexpr Key<std::string> phase_obstacle_kind{"phase.obstacle_kind"};
inline constexpr Key<bool> phase_thermostat{"phase.thermostat"};
inline constexpr Key<double> phase_thermostat_T{"phase.thermostat_T"};
// A standing sound wave between the walls in y (seed 003 §4.2, the sound_speed study):
// v_y += A1 sin(π y'/L') + A2 sin(2π y'/L') for every disk, y' = y − r and L' = Ly − 2r
// the span its centre may reach; with it stats.csv gets the projections wave_vy1, wave_vy2.
inline constexpr Key<std::array<double, 2>> phase_wave_vy{"phase.wave_vy"};

// The fluid's measured transport numbers (agents/medium.cpp), optional: with a stream and
// an obstacle the caption and run.json give Re = U D / nu and Ma = U / sound_speed.
inline constexpr TableKey medium{"medium"};
inline constexpr Key<double> medium_nu{"medium.nu"};
inline constexpr Key<double> medium_sound_speed{"medium.sound_speed"};

// The area fraction the scene asks for, from whichever of area_fraction, n or N it gives
// (0 when none): the one conversion the cross-checks use.
double requested_area_fraction(const Scene& sc);

// The obstacle surface in effect in phase k (k = npos: before the first phase): the kind of
// the last [[phase]] up to k that sets obstacle_kind, else boundary.obstacle.kind.
std::string obstacle_kind_at(const Scene& sc, std::size_t k);
// Whether the obstacle restitution set by phase `from` (npos: boundary.obstacle.r) is used:
// a slip or flip surface is in effect at some time before the next phase setting
// obstacle_r (the thermal surface re-emits and has no restitution).
bool obstacle_r_used(const Scene& sc, std::size_t from);

// Declares [system], [boundary], [boundary.obstacle], [boundary.stream], [thermostat] and
// their checks.
void declare(Schema& s);

}  // namespace grainflow::scenes::ed_keys
