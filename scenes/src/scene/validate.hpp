// Validation of a parsed scene table against the schema (SPEC.md §3b): unknown sections and
// keys (with "did you mean"), wrong types, out-of-range values, bad choices — all collected
// with file:line:column — then defaults filled in and the cross-key checks run.
// Internal to the scene layer: the only header besides scene_overrides.hpp that sees toml++.
#pragma once
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "scenes/src/scene/scene_error.hpp"

namespace grainflow::scenes {

class Schema;
class SchemaCatalog;

// Where values that did not come from the file came from: dotted path ("run.seed",
// "system.group[1]") -> "--set run.seed=3". A path inherits the origin of its longest prefix.
using Origins = std::map<std::string, std::string, std::less<>>;

struct ValidatedScene {
  toml::table effective;  // every schema key present (defaults filled), floats stored as floats
  std::string engine;     // "" when run.engine is missing or invalid
  const Schema* schema = nullptr;
};

// Validates `doc` (a scene file after --set overrides). `source_name` is used for issues
// that have no position. Appends to `issues`; the result is meaningful only if none were added.
ValidatedScene validate_scene(const toml::table& doc, const Origins& origins, const std::string& source_name,
                              const SchemaCatalog& catalog, std::vector<SceneIssue>& issues);

// The location text of the node at `path` in `doc`: "file:line:col", the --set that put
// it there, or `source_name`.
std::string locate(const toml::table& doc, std::string_view path, const Origins& origins,
                   const std::string& source_name);

// The --set that put `path` (or an ancestor of it) there, if any.
std::optional<std::string> find_origin(const Origins& origins, std::string_view path);

// TOML text of a node ("[8, 480]", "\"slip\"", "{…}"): the whole value.
std::string node_text(const toml::node& n);
// The same for messages, elided: arrays beyond 8 elements and strings beyond 60
// characters are cut with their size ("[1, 2, …, … (12000000 elements)]").
std::string brief_text(const toml::node& n);
std::string node_type_name(const toml::node& n);

}  // namespace grainflow::scenes
