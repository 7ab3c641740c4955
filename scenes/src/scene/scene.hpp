// A validated scene (SPEC.md §3b): every key of the schema with its value or default,
// read through the key handles its consumers declared (scene.get(sample_keys::exposure)).
// load_scene() parses, applies --set and validates against a SchemaCatalog.
#pragma once
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "scenes/src/scene/scene_error.hpp"
#include "scenes/src/scene/schema.hpp"

namespace grainflow::scenes {

class Scene {
public:
  struct Impl;
  explicit Scene(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}

  // Value of a key by dotted path; array-of-table elements by index:
  // "system.group[1].radius". Supported T: bool, std::int64_t, int, double, std::string,
  // std::vector<double|std::int64_t|int|bool|std::string>, std::array<double|int|bool, 2|3>.
  // A key that is absent (optional key not given) or has another type is a programming
  // error (std::logic_error): validation guarantees the types of every schema key.
  template <class T> T get(std::string_view path) const;
  // Same for an optional key: std::nullopt when absent.
  template <class T> std::optional<T> find(std::string_view path) const {
    if (!has(path)) return std::nullopt;
    return get<T>(path);
  }
  bool has(std::string_view path) const;
  // Number of elements of an array of tables ("system.group"); 0 when absent.
  std::size_t count(std::string_view path) const;

  // Reads through the key's typed handle, the one its consumer declared it with; these
  // reads are recorded (keys_read) so tests find declared keys that nothing consumes.
  template <class T> T get(const Key<T>& key) const {
    note_read(key.path);
    return get<T>(key.path);
  }
  template <class T> std::optional<T> find(const Key<T>& key) const {
    note_read(key.path);
    return find<T>(key.path);
  }
  template <class T> bool has(const Key<T>& key) const {
    note_read(key.path);
    return has(key.path);
  }
  // Element `index` of an array of tables: key "system.group.radius" reads
  // "system.group[index].radius".
  template <class T> T get(const Key<T>& key, std::size_t index) const {
    note_read(key.path);
    return get<T>(std::string(key.table()) + "[" + std::to_string(index) + "]." + std::string(key.name()));
  }
  bool has(TableKey table) const { return has(table.path); }
  std::size_t count(TableKey table) const { return count(table.path); }
  // Dotted paths (no indices) read through Key handles since the scene was loaded.
  std::vector<std::string> keys_read() const;

  const std::string& engine() const;
  // The scene file this came from ("" for a string scene) and the --set overrides applied.
  const std::filesystem::path& source() const;
  const std::vector<std::string>& overrides() const;
  const Schema& schema() const;

  // The effective scene as TOML, in schema order, each key with its doc as a comment.
  std::string to_toml() const;
  // Hash of every value but those of keys marked may_change_on_resume (run.until, outputs
  // that decide nothing a checkpoint holds): a checkpoint records it, and a resume with a
  // scene of another fingerprint is refused.
  std::uint64_t fingerprint() const;

  const Impl& impl() const { return *impl_; }

private:
  void note_read(std::string_view path) const;
  std::shared_ptr<const Impl> impl_;
};

// Reads a scene file, applies `--set section.key=value` overrides (each string is
// "section.key=value"), validates against the catalog's schema for its run.engine. Throws
// SceneError with every problem found (file:line:column, key, value, what is allowed), or
// grainflow::Error when the file cannot be read. (run/scene_catalog.hpp has the versions
// with the application's catalog.)
Scene load_scene(const std::filesystem::path& path, const std::vector<std::string>& overrides,
                 const SchemaCatalog& catalog);
// The same from TOML text; `source_name` is used in messages.
Scene parse_scene(std::string_view toml_text, std::string_view source_name, const std::vector<std::string>& overrides,
                  const SchemaCatalog& catalog);

// Writes scene.to_toml() to `path` atomically (temporary name + rename).
void write_effective_scene(const Scene& scene, const std::filesystem::path& path);

}  // namespace grainflow::scenes
