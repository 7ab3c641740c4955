// The declarative schema of a scene file (SPEC.md §3b): every table and key a scene may
// hold, with type, default, allowed range or choices, a one-line doc and a unit. One schema
// serves both engines: common sections plus the [system]/[boundary] keys an engine registers.
#pragma once
#include <concepts>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace grainflow::scenes {

class Scene;
class SceneCheck;

// A typed handle on one key of the schema, by its dotted path without array indices
// ("system.kT", "system.group.radius"). The code that consumes a key declares it with this
// handle (TableSpec::add_*) and reads it with the same one (Scene::get(key)), so a path is
// spelled once and a test can find declared keys that nothing reads (Scene::keys_read).
template <class T> struct Key {
  std::string_view path;
  constexpr std::string_view table() const { return path.substr(0, path.rfind('.')); }
  constexpr std::string_view name() const { return path.substr(path.rfind('.') + 1); }
};
// A handle on a table: optional tables are read by presence (Scene::has), arrays of tables
// by count (Scene::count).
struct TableKey {
  std::string_view path;
};

enum class KeyType {
  Bool,         // true | false
  Int,          // TOML integer
  Float,        // TOML float; an integer is accepted and promoted
  String,       // any string
  Enum,         // one string out of `choices`
  NumberArray,  // array of numbers (Int or Float elements per `element_integer`)
  BoolArray,    // array of booleans
  StringArray,  // array of strings (restricted to `choices` when not empty)
};

std::string_view key_type_name(KeyType t);

// A default value: the alternative used must match the key's type.
using DefaultValue = std::variant<std::monostate, bool, std::int64_t, double, std::string,
                                  std::vector<double>, std::vector<std::int64_t>, std::vector<bool>,
                                  std::vector<std::string>>;

enum class Presence {
  Defaulted,  // missing => default value filled in (the effective scene always holds it)
  Required,   // missing => error
  Optional,   // missing => stays absent (alternatives such as area_fraction | n | N)
};

struct KeySpec {
  std::string name;  // relative to its table
  KeyType type = KeyType::Float;
  Presence presence = Presence::Defaulted;
  DefaultValue default_value;
  std::string doc;
  std::string unit;  // empty for dimensionless / not applicable

  // Numeric range, for numbers and for every element of a NumberArray.
  std::optional<double> min, max;
  bool min_exclusive = false, max_exclusive = false;
  // Enum and StringArray choices.
  std::vector<std::string> choices;
  // Arrays: allowed length (equal for fixed-length arrays such as box = [Lx, Ly]).
  std::size_t min_length = 0, max_length = SIZE_MAX;
  bool element_integer = false;  // NumberArray of integers
  std::vector<std::string> element_names;  // e.g. {"Lx","Ly"} for messages and docs
  std::string note;  // extra sentence appended to range errors and docs
  // A file path relative to the scene file: the effective scene.toml of a run folder
  // writes it resolved, so `grainflow run DIR/scene.toml` finds the same file.
  bool is_path = false;
  // `grainflow run --resume --set` may change it: it decides nothing the checkpointed state
  // depends on (run.until, run.max_wall, output.checkpoint_every).
  bool resumable = false;

  // Fluent refinements, so registration reads like a table.
  KeySpec& at_least(double v) { min = v; min_exclusive = false; return *this; }
  KeySpec& above(double v) { min = v; min_exclusive = true; return *this; }
  KeySpec& at_most(double v) { max = v; max_exclusive = false; return *this; }
  KeySpec& below(double v) { max = v; max_exclusive = true; return *this; }
  KeySpec& required() { presence = Presence::Required; default_value = {}; return *this; }
  KeySpec& optional() { presence = Presence::Optional; default_value = {}; return *this; }
  KeySpec& length(std::size_t lo, std::size_t hi) { min_length = lo; max_length = hi; return *this; }
  KeySpec& with_note(std::string n) { note = std::move(n); return *this; }
  KeySpec& path() { is_path = true; return *this; }
  KeySpec& may_change_on_resume() { resumable = true; return *this; }

  // "0 < value ≤ 1", "" when unbounded.
  std::string range_text() const;
  // "integer", "number", "one of \"a\" | \"b\"", "array of 2 integers [nx, ny]", …
  std::string allowed_text() const;
};

enum class TableKind {
  Section,   // always present in the effective scene (defaults filled)
  Optional,  // present only when the file (or a --set) mentions it, e.g. [boundary.obstacle]
  Array,     // array of tables, [[system.group]]; each element is checked against the keys
};

class TableSpec {
public:
  TableSpec(std::string path, TableKind kind, std::string doc)
      : path_(std::move(path)), kind_(kind), doc_(std::move(doc)) {}

  const std::string& path() const { return path_; }
  TableKind kind() const { return kind_; }
  const std::string& doc() const { return doc_; }
  const std::vector<KeySpec>& keys() const { return keys_; }
  const KeySpec* find_key(std::string_view name) const;
  std::size_t min_count = 0;  // Array tables: fewest elements

  // Keys are declared through their typed handles (Key<T> above), the same handles the
  // code that consumes them reads with; the handle's table must be this table.
  KeySpec& add_bool(Key<bool> key, bool def, std::string doc);
  template <class I>
    requires std::same_as<I, std::int64_t> || std::same_as<I, int>
  KeySpec& add_int(Key<I> key, std::int64_t def, std::string doc, std::string unit = {}) {
    return add_int_impl(key.path, def, std::move(doc), std::move(unit));
  }
  KeySpec& add_float(Key<double> key, double def, std::string doc, std::string unit = {});
  KeySpec& add_string(Key<std::string> key, std::string def, std::string doc);
  KeySpec& add_enum(Key<std::string> key, std::vector<std::string> choices, std::string def, std::string doc);
  template <class A>
    requires std::same_as<typename A::value_type, double>
  KeySpec& add_float_array(Key<A> key, std::vector<double> def, std::vector<std::string> element_names,
                           std::string doc, std::string unit = {}) {
    return add_float_array_impl(key.path, std::move(def), std::move(element_names), std::move(doc), std::move(unit));
  }
  template <class A>
    requires std::same_as<typename A::value_type, int> || std::same_as<typename A::value_type, std::int64_t>
  KeySpec& add_int_array(Key<A> key, std::vector<std::int64_t> def, std::vector<std::string> element_names,
                         std::string doc, std::string unit = {}) {
    return add_int_array_impl(key.path, std::move(def), std::move(element_names), std::move(doc), std::move(unit));
  }
  template <class A>
    requires std::same_as<typename A::value_type, bool>
  KeySpec& add_bool_array(Key<A> key, std::vector<bool> def, std::vector<std::string> element_names,
                          std::string doc) {
    return add_bool_array_impl(key.path, std::move(def), std::move(element_names), std::move(doc));
  }
  KeySpec& add_string_array(Key<std::vector<std::string>> key, std::vector<std::string> choices,
                            std::vector<std::string> def, std::string doc);

private:
  KeySpec& add(std::string_view key_path, KeySpec k);
  KeySpec& add_int_impl(std::string_view path, std::int64_t def, std::string doc, std::string unit);
  KeySpec& add_float_array_impl(std::string_view path, std::vector<double> def, std::vector<std::string> names,
                                std::string doc, std::string unit);
  KeySpec& add_int_array_impl(std::string_view path, std::vector<std::int64_t> def, std::vector<std::string> names,
                              std::string doc, std::string unit);
  KeySpec& add_bool_array_impl(std::string_view path, std::vector<bool> def, std::vector<std::string> names,
                               std::string doc);
  std::string path_;
  TableKind kind_;
  std::string doc_;
  std::vector<KeySpec> keys_;
};

// Reports a cross-key problem (e.g. "give exactly one of area_fraction, n, N") at the key.
class SceneCheck {
public:
  virtual ~SceneCheck() = default;
  virtual void fail(std::string_view key_path, std::string message) = 0;
};

// A rule involving several keys, run on the effective scene once every key is valid.
using CrossCheck = std::function<void(const Scene&, SceneCheck&)>;

class Schema {
public:
  // Tables are kept in registration order, which is the order of the effective scene file.
  // A table's parent ("boundary" for "boundary.obstacle") must be registered first.
  TableSpec& section(std::string path, std::string doc) { return add_table(std::move(path), TableKind::Section, std::move(doc)); }
  TableSpec& optional_table(std::string path, std::string doc) { return add_table(std::move(path), TableKind::Optional, std::move(doc)); }
  TableSpec& array_table(std::string path, std::string doc) { return add_table(std::move(path), TableKind::Array, std::move(doc)); }
  TableSpec& optional_table(TableKey t, std::string doc) { return optional_table(std::string(t.path), std::move(doc)); }
  TableSpec& array_table(TableKey t, std::string doc) { return array_table(std::string(t.path), std::move(doc)); }
  // Adds keys to an existing table (an engine adding [sample] plane, say).
  TableSpec& table(std::string_view path);
  void add_check(CrossCheck c) { checks_.push_back(std::move(c)); }

  const std::vector<TableSpec>& tables() const { return tables_; }
  const TableSpec* find_table(std::string_view path) const;
  const std::vector<CrossCheck>& checks() const { return checks_; }
  // Key by full dotted path without array indices ("system.group.radius").
  const KeySpec* find_key(std::string_view dotted_path) const;

private:
  TableSpec& add_table(std::string path, TableKind kind, std::string doc);
  std::vector<TableSpec> tables_;
  std::vector<CrossCheck> checks_;
};

// Which schema a scene is checked against. The scene layer knows no engine: whoever loads
// scenes supplies the catalog (run/scene_catalog.hpp assembles it from the engine and
// output tables).
class SchemaCatalog {
public:
  virtual ~SchemaCatalog() = default;
  // The sections every scene has, to read run.engine before the engine is known.
  virtual const Schema& common() const = 0;
  // The full schema a run.engine name selects; nullptr for an unknown name.
  virtual const Schema* for_engine(std::string_view engine) const = 0;
  // Sections only engines fill ("system", "boundary"): not reported as unknown while
  // run.engine itself is invalid (its own error is).
  virtual std::span<const std::string> engine_sections() const = 0;
};

// Human-readable reference of every key (type, default, range, unit, doc).
std::string describe_schema(const Schema& s);

}  // namespace grainflow::scenes
