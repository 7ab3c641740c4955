// The [run] section every scene has, whatever its engine: which engine runs it, for how
// long, the seed of its one random generator and a title. Part of what a Scene is
// (Scene::engine() is run.engine), so it sits in the scene room; the names run.engine may
// take are the engine table's, handed in by whoever assembles the schema.
#pragma once
#include <cstdint>
#include <span>
#include <string>

#include "scenes/src/scene/schema.hpp"

namespace grainflow::scenes::run_keys {

inline constexpr Key<std::string> engine{"run.engine"};
inline constexpr Key<double> until{"run.until"};
inline constexpr Key<std::int64_t> steps{"run.steps"};
inline constexpr Key<std::int64_t> seed{"run.seed"};
inline constexpr Key<std::string> title{"run.title"};

// Declares [run]; `engine_names` are the values run.engine may take.
void declare(Schema& s, std::span<const std::string> engine_names);

}  // namespace grainflow::scenes::run_keys
