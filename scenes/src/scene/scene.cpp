#include "scenes/src/scene/scene.hpp"

#include <algorithm>
#include <array>
#include <climits>
#include <utility>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "engine/io/atomic_file.hpp"
#include "engine/core/error.hpp"
#include "scenes/src/scene/run_keys.hpp"
#include "scenes/src/scene/scene_impl.hpp"
#include "scenes/src/scene/overrides.hpp"
#include "scenes/src/scene/validate.hpp"

namespace grainflow::scenes {

namespace {

[[noreturn]] void misuse(std::string_view path, std::string_view what) {
  throw std::logic_error("Scene::get(\"" + std::string(path) + "\"): " + std::string(what));
}

const toml::node& node_at(const toml::table& t, std::string_view path) {
  const toml::node* n = toml::at_path(t, path).node();
  if (!n) misuse(path, "key absent (optional key not given, or not in the schema)");
  return *n;
}

template <class T> T scalar(const toml::node& n, std::string_view path);

template <> bool scalar<bool>(const toml::node& n, std::string_view path) {
  if (!n.is_boolean()) misuse(path, "not a boolean");
  return n.as_boolean()->get();
}
template <> std::int64_t scalar<std::int64_t>(const toml::node& n, std::string_view path) {
  if (!n.is_integer()) misuse(path, "not an integer");
  return n.as_integer()->get();
}
template <> int scalar<int>(const toml::node& n, std::string_view path) {
  const std::int64_t v = scalar<std::int64_t>(n, path);
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max()) misuse(path, "does not fit an int");
  return int(v);
}
template <> double scalar<double>(const toml::node& n, std::string_view path) {
  if (n.is_integer()) return double(n.as_integer()->get());
  if (!n.is_floating_point()) misuse(path, "not a number");
  return n.as_floating_point()->get();
}
template <> std::string scalar<std::string>(const toml::node& n, std::string_view path) {
  if (!n.is_string()) misuse(path, "not a string");
  return n.as_string()->get();
}

template <class E> std::vector<E> vec(const toml::node& n, std::string_view path) {
  const toml::array* a = n.as_array();
  if (!a) misuse(path, "not an array");
  std::vector<E> out;
  out.reserve(a->size());
  for (const auto& e : *a) out.push_back(scalar<E>(e, path));
  return out;
}

template <class E, std::size_t N> std::array<E, N> arr(const toml::node& n, std::string_view path) {
  const auto v = vec<E>(n, path);
  if (v.size() != N) misuse(path, "array has " + std::to_string(v.size()) + " elements, " + std::to_string(N) + " asked");
  std::array<E, N> out;
  for (std::size_t i = 0; i < N; ++i) out[i] = v[i];
  return out;
}

template <class T> struct Getter {
  static T get(const toml::node& n, std::string_view p) { return scalar<T>(n, p); }
};
template <class E> struct Getter<std::vector<E>> {
  static std::vector<E> get(const toml::node& n, std::string_view p) { return vec<E>(n, p); }
};
template <class E, std::size_t N> struct Getter<std::array<E, N>> {
  static std::array<E, N> get(const toml::node& n, std::string_view p) { return arr<E, N>(n, p); }
};

std::string read_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw Error("cannot read scene '" + path.string() + "': it is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read scene '" + path.string() + "': " + (std::filesystem::exists(path, ec) ? "permission denied" : "no such file"));
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

// (line, column) of a "file:line:col" location; issues without one sort after all others.
std::pair<unsigned long, unsigned long> file_position(const std::string& loc) {
  constexpr auto none = std::pair<unsigned long, unsigned long>(ULONG_MAX, ULONG_MAX);
  const auto c2 = loc.rfind(':');
  if (c2 == std::string::npos || c2 == 0) return none;
  const auto c1 = loc.rfind(':', c2 - 1);
  if (c1 == std::string::npos) return none;
  const std::string line = loc.substr(c1 + 1, c2 - c1 - 1), col = loc.substr(c2 + 1);
  auto digits = [](const std::string& x) {
    return !x.empty() && x.find_first_not_of("0123456789") == std::string::npos;
  };
  if (!digits(line) || !digits(col) || loc.rfind("--set ", 0) == 0) return none;
  return {std::stoul(line), std::stoul(col)};
}

Scene build(std::string_view text, const std::string& source_name, const std::filesystem::path& source_path,
            const std::vector<std::string>& overrides, const SchemaCatalog& catalog) {
  std::vector<SceneIssue> issues;
  toml::table doc;
  try {
    doc = toml::parse(text, std::string_view(source_name));
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    issues.push_back({source_name + ":" + std::to_string(b.line) + ":" + std::to_string(b.column), "",
                      "TOML syntax error: " + std::string(e.description())});
    throw SceneError(std::move(issues));
  }
  Origins origins;
  for (const auto& arg : overrides) {
    const Override o = parse_override(arg);
    apply_override(doc, o, origins, issues);
  }
  ValidatedScene v = validate_scene(doc, origins, source_name, catalog, issues);
  if (!issues.empty()) {
    // Tables iterate in key order; the user reads the file top to bottom, then the --sets.
    std::stable_sort(issues.begin(), issues.end(), [](const SceneIssue& a, const SceneIssue& b) {
      return file_position(a.location) < file_position(b.location);
    });
    throw SceneError(std::move(issues));
  }
  auto impl = std::make_shared<Scene::Impl>();
  impl->table = std::move(v.effective);
  impl->engine = v.engine;
  impl->schema = v.schema;
  impl->source = source_path;
  impl->overrides = overrides;
  return Scene(std::move(impl));
}

}  // namespace

template <class T> T Scene::get(std::string_view path) const {
  return Getter<T>::get(node_at(impl_->table, path), path);
}

#define GRAINFLOW_SCENE_GET(T) template T Scene::get<T>(std::string_view) const;
GRAINFLOW_SCENE_GET(bool)
GRAINFLOW_SCENE_GET(int)
GRAINFLOW_SCENE_GET(std::int64_t)
GRAINFLOW_SCENE_GET(double)
GRAINFLOW_SCENE_GET(std::string)
GRAINFLOW_SCENE_GET(std::vector<bool>)
GRAINFLOW_SCENE_GET(std::vector<int>)
GRAINFLOW_SCENE_GET(std::vector<std::int64_t>)
GRAINFLOW_SCENE_GET(std::vector<double>)
GRAINFLOW_SCENE_GET(std::vector<std::string>)
using ArrD2 = std::array<double, 2>;
using ArrD3 = std::array<double, 3>;
using ArrI2 = std::array<int, 2>;
using ArrI3 = std::array<int, 3>;
using ArrB2 = std::array<bool, 2>;
using ArrB3 = std::array<bool, 3>;
GRAINFLOW_SCENE_GET(ArrD2)
GRAINFLOW_SCENE_GET(ArrD3)
GRAINFLOW_SCENE_GET(ArrI2)
GRAINFLOW_SCENE_GET(ArrI3)
GRAINFLOW_SCENE_GET(ArrB2)
GRAINFLOW_SCENE_GET(ArrB3)
#undef GRAINFLOW_SCENE_GET

bool Scene::has(std::string_view path) const { return static_cast<bool>(toml::at_path(impl_->table, path)); }

std::size_t Scene::count(std::string_view path) const {
  const toml::node* n = toml::at_path(impl_->table, path).node();
  if (!n) return 0;
  const toml::array* a = n->as_array();
  if (!a || !a->is_array_of_tables()) misuse(path, "not an array of tables");
  return a->size();
}

const std::string& Scene::engine() const {
  note_read(run_keys::engine.path);  // the one consumer of run.engine
  return impl_->engine;
}
const std::filesystem::path& Scene::source() const { return impl_->source; }
const std::vector<std::string>& Scene::overrides() const { return impl_->overrides; }
const Schema& Scene::schema() const { return *impl_->schema; }

Scene load_scene(const std::filesystem::path& path, const std::vector<std::string>& overrides,
                 const SchemaCatalog& catalog) {
  const std::string text = read_file(path);
  return build(text, path.string(), path, overrides, catalog);
}

Scene parse_scene(std::string_view toml_text, std::string_view source_name, const std::vector<std::string>& overrides,
                  const SchemaCatalog& catalog) {
  return build(toml_text, std::string(source_name), {}, overrides, catalog);
}

void Scene::note_read(std::string_view path) const {
  std::lock_guard lock(impl_->read_mutex);
  if (impl_->read.find(path) == impl_->read.end()) impl_->read.emplace(path);
}

std::vector<std::string> Scene::keys_read() const {
  std::lock_guard lock(impl_->read_mutex);
  return {impl_->read.begin(), impl_->read.end()};
}

void write_effective_scene(const Scene& scene, const std::filesystem::path& path) {
  io::write_text_atomically(path, scene.to_toml());
}

}  // namespace grainflow::scenes
