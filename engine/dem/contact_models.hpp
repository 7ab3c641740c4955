// The tables of DEM contact sub-models, one per family (seed 000 §2.4 Walton models,
// ch. 5 van der Waals; LAMMPS gran/hooke/history for comparison runs). Everything that
// picks, names, checks, mixes or composes a sub-model is driven by these three lists.
#pragma once
#include "engine/dem/history_tangential.hpp"
#include "engine/dem/hooke_normal.hpp"
#include "engine/dem/sub_model.hpp"
#include "engine/dem/vdw_cohesion.hpp"
#include "engine/dem/walton_normal.hpp"
#include "engine/dem/walton_tangential.hpp"

namespace grainflow::dem {

// One row per sub-model. A row's index is what ContactModelSpec and checkpoints store:
// append new rows, never reorder (a new model: its header, included above, and its row).
using NormalModels = TypeList<WaltonNormal, HookeNormal>;
using TangentialModels = TypeList<WaltonTangential, HistoryTangential, NoTangential>;
using CohesionModels = TypeList<NoCohesion, VdwCohesion>;

}  // namespace grainflow::dem
