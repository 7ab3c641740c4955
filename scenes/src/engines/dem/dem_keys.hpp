// The keys of the 3D soft-sphere DEM engine (seed 000 ch. 2–5), declared by dem_keys.cpp
// and read by dem_runner.cpp through these handles. Units: SI (m, kg, s, N, J).
#pragma once
#include <array>
#include <cstdint>
#include <string>

#include "scenes/src/scene/schema.hpp"

namespace grainflow::scenes::dem_keys {

inline constexpr Key<std::string> plane{"sample.plane"};
inline constexpr Key<std::array<double, 2>> slab{"sample.slab"};
inline constexpr Key<bool> pair_csv{"output.pair_csv"};
inline constexpr Key<std::int64_t> pair_every{"output.pair_every"};

inline constexpr Key<std::array<double, 3>> box{"system.box"};
inline constexpr Key<std::array<double, 3>> origin{"system.origin"};
inline constexpr Key<std::array<double, 3>> gravity{"system.gravity"};
inline constexpr Key<double> dt{"system.dt"};
inline constexpr Key<std::int64_t> steps_per_collision{"system.steps_per_collision"};
inline constexpr Key<std::string> neighbor_search{"system.neighbor_search"};
inline constexpr Key<double> skin{"system.skin"};

// Sub-model names come from engine/dem's tables (contact_models.hpp); cohesion is chosen by
// the presence of [system.vdw], whose keys are its coefficients.
inline constexpr Key<std::string> normal_model{"system.contact.normal"};
inline constexpr Key<std::string> tangential_model{"system.contact.tangential"};
inline constexpr Key<double> kn{"system.contact.kn"};
inline constexpr Key<double> kt{"system.contact.kt"};
inline constexpr Key<double> e{"system.contact.e"};
inline constexpr Key<double> mu{"system.contact.mu"};
// LAMMPS pair_style gran/hooke/history Kn Kt gamma_n gamma_t xmu dampflag: kn, kt,
// gamma_n, gamma_t, mu (= xmu), dampflag; Walton's K2 and tangential exponent γ.
inline constexpr Key<double> gamma_n{"system.contact.gamma_n"};
inline constexpr Key<double> gamma_t{"system.contact.gamma_t"};
inline constexpr Key<bool> dampflag{"system.contact.dampflag"};
inline constexpr Key<double> k2{"system.contact.k2"};
inline constexpr Key<double> walton_gamma{"system.contact.walton_gamma"};

inline constexpr TableKey group{"system.group"};
inline constexpr Key<std::int64_t> group_N{"system.group.N"};
inline constexpr Key<double> group_radius{"system.group.radius"};
inline constexpr Key<double> group_density{"system.group.density"};
inline constexpr Key<double> group_e{"system.group.e"};
inline constexpr Key<double> group_mu{"system.group.mu"};
inline constexpr Key<double> group_kn{"system.group.kn"};
inline constexpr Key<double> group_kt{"system.group.kt"};
inline constexpr Key<double> group_k2{"system.group.k2"};
inline constexpr Key<double> group_gamma_n{"system.group.gamma_n"};
inline constexpr Key<double> group_gamma_t{"system.group.gamma_t"};

inline constexpr TableKey vdw{"system.vdw"};
inline constexpr Key<double> vdw_A{"system.vdw.A"};
inline constexpr Key<double> vdw_alpha_min{"system.vdw.alpha_min"};
inline constexpr Key<double> vdw_cutoff{"system.vdw.cutoff"};
inline constexpr Key<double> vdw_asperity_radius{"system.vdw.asperity_radius"};
inline constexpr Key<double> vdw_r_ss{"system.vdw.r_ss"};

inline constexpr Key<std::string> initial_kind{"system.initial.kind"};
// system.initial.file, frame and ignore: initial_file.hpp, shared with the ED engine.
inline constexpr Key<std::int64_t> grow_steps{"system.initial.grow_steps"};
inline constexpr Key<double> grow_from{"system.initial.grow_from"};
inline constexpr Key<double> fill_height{"system.initial.fill_height"};

inline constexpr Key<std::array<bool, 3>> periodic{"boundary.periodic"};
inline constexpr Key<std::string> top{"boundary.top"};
inline constexpr Key<std::array<double, 2>> top_velocity{"boundary.top_velocity"};
inline constexpr Key<std::array<double, 2>> bottom_velocity{"boundary.bottom_velocity"};

// Declares [sample] plane and slab, [output] pair_csv/pair_every, [system…], [boundary] and checks.
void declare(Schema& s);

}  // namespace grainflow::scenes::dem_keys
