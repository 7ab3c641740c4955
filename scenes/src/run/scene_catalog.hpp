// The application's scene catalog: the schema of a run.engine, assembled from every room
// that consumes keys — [run] (scene/run_keys), [sample] (engines/sampling), [render]
// (render_keys, with the engine's colour attributes), [output] (the output table) and the
// engine's own keys (the engine table). The one place where the rooms' keys meet.
#pragma once
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "scenes/src/scene/scene.hpp"
#include "scenes/src/scene/schema.hpp"

namespace grainflow::scenes {

const SchemaCatalog& scene_catalog();
// The full schema of an engine. Throws grainflow::Error for an unknown engine.
const Schema& schema_for_engine(std::string_view engine);

// load_scene / parse_scene (scene/scene.hpp) with the application's catalog.
Scene load_scene(const std::filesystem::path& path, const std::vector<std::string>& overrides = {});
Scene parse_scene(std::string_view toml_text, std::string_view source_name = "scene",
                  const std::vector<std::string>& overrides = {});

}  // namespace grainflow::scenes
