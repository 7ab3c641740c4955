// `--set section.key=value` overrides (SPEC.md §3b): the value is read as TOML
// (`run.seed=3`, `render.size=[640,480]`, `boundary.obstacle.kind="slip"`), or as a plain
// string when it is not TOML (`run.engine=dem`); applied to the parsed file before
// validation, so an override is checked exactly like the file.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "scenes/src/scene/scene_error.hpp"
#include "scenes/src/scene/validate.hpp"

namespace grainflow::scenes {

struct Override {
  std::string key;    // "boundary.obstacle.kind", "system.group[1].radius"
  std::string value;  // text after '='
  std::string text;   // "--set key=value" as the user wrote it, for messages
};

// Splits "key=value". Throws grainflow::Error when there is no '=' or the key is malformed.
Override parse_override(std::string_view arg);

// Applies one override to `doc` and records its origin. Problems (value not TOML, a path
// through a non-table) are appended to `issues`; the key itself is checked by validation.
void apply_override(toml::table& doc, const Override& o, Origins& origins, std::vector<SceneIssue>& issues);

}  // namespace grainflow::scenes
