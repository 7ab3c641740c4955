#include "scenes/src/scene/validate.hpp"

#include <cmath>
#include <memory>
#include <sstream>

#include "scenes/src/scene/scene_impl.hpp"
#include "scenes/src/scene/schema.hpp"
#include "scenes/src/scene/suggest.hpp"
#include "scenes/src/scene/toml_text.hpp"

namespace grainflow::scenes {

std::string node_type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a float";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::date: return "a date";
    case toml::node_type::time: return "a time";
    case toml::node_type::date_time: return "a date-time";
    default: return "nothing";
  }
}

std::string node_text(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string: return toml_string(n.as_string()->get());
    case toml::node_type::integer: return toml_int(n.as_integer()->get());
    case toml::node_type::floating_point: return toml_float(n.as_floating_point()->get());
    case toml::node_type::boolean: return n.as_boolean()->get() ? "true" : "false";
    case toml::node_type::array: {
      std::string s = "[";
      const auto& a = *n.as_array();
      for (std::size_t i = 0; i < a.size(); ++i) s += (i ? ", " : "") + node_text(a[i]);
      return s + "]";
    }
    case toml::node_type::table: return "{…}";
    default: {
      std::ostringstream os;  // dates and times
      if (const auto* d = n.as_date()) os << *d;
      else if (const auto* t = n.as_time()) os << *t;
      else if (const auto* dt = n.as_date_time()) os << *dt;
      return os.str();
    }
  }
}

std::string brief_text(const toml::node& n) {
  constexpr std::size_t kMaxElements = 8, kMaxChars = 60;
  if (const auto* a = n.as_array(); a && a->size() > kMaxElements) {
    std::string s = "[";
    for (std::size_t i = 0; i < kMaxElements; ++i) s += (i ? ", " : "") + brief_text((*a)[i]);
    return s + ", … (" + std::to_string(a->size()) + " elements)]";
  }
  if (const auto* str = n.as_string(); str && str->get().size() > kMaxChars)
    return toml_string(str->get().substr(0, kMaxChars)) + "… (" + std::to_string(str->get().size()) + " characters)";
  std::string s = node_text(n);
  if (s.size() > 4 * kMaxChars) s = s.substr(0, 4 * kMaxChars) + "…";
  return s;
}

std::optional<std::string> find_origin(const Origins& origins, std::string_view path) {
  std::string_view p = path;
  while (!p.empty()) {
    if (auto it = origins.find(p); it != origins.end()) return it->second;
    const auto cut = p.find_last_of(".[");
    if (cut == std::string_view::npos) break;
    p = p.substr(0, cut);
  }
  return std::nullopt;
}

std::string locate(const toml::table& doc, std::string_view path, const Origins& origins,
                   const std::string& source_name) {
  // An override wins: its node has no position in the file.
  if (auto o = find_origin(origins, path)) return *o;
  // The node itself, else its closest ancestor with a position (implicit tables have none).
  std::string_view p = path;
  while (!p.empty()) {
    const toml::node* n = toml::at_path(doc, p).node();
    if (n && n->source().begin) {
      const auto& src = n->source();
      return (src.path ? *src.path : source_name) + ":" + std::to_string(src.begin.line) + ":" +
             std::to_string(src.begin.column);
    }
    const auto cut = p.find_last_of(".[");
    if (cut == std::string_view::npos) break;
    p = p.substr(0, cut);
  }
  return source_name;
}

namespace {

class Validator {
public:
  Validator(const toml::table& doc, const Origins& origins, const std::string& source, const Schema& schema,
            bool engine_known, std::span<const std::string> engine_sections, std::vector<SceneIssue>& issues)
      : doc_(doc), origins_(origins), source_(source), schema_(schema), engine_known_(engine_known),
        engine_sections_(engine_sections), issues_(issues) {}

  toml::table run() {
    toml::table out;
    for (auto&& [k, node] : doc_) {
      const std::string name(k.str());
      if (const TableSpec* t = schema_.find_table(name)) {
        table_entry(*t, node, name, out, name);
      } else if (!engine_known_ && is_engine_section(name)) {
        // Checked once run.engine is valid; its own error is already reported.
      } else {
        unknown_top_level(k, name, node);
      }
    }
    fill_missing_children(nullptr, "", doc_, out);
    return out;
  }

private:
  bool is_engine_section(std::string_view name) const {
    for (const auto& s : engine_sections_)
      if (s == name) return true;
    return false;
  }

  void issue(std::string_view path, std::string message) {
    issues_.push_back({locate(doc_, path, origins_, source_), std::string(path), std::move(message)});
  }

  // Unknown keys are reported at the key, not at its value.
  void issue_at_key(const toml::key& k, std::string_view path, std::string message) {
    const auto& src = k.source();
    if (find_origin(origins_, path) || !src.begin) return issue(path, std::move(message));
    issues_.push_back({(src.path ? *src.path : source_) + ":" + std::to_string(src.begin.line) + ":" +
                           std::to_string(src.begin.column),
                       std::string(path), std::move(message)});
  }

  void unknown_top_level(const toml::key& k, const std::string& name, const toml::node& node) {
    std::vector<std::string> sections;
    for (const auto& t : schema_.tables())
      if (t.path().find('.') == std::string::npos) sections.push_back(t.path());
    if (!engine_known_)
      for (const auto& s : engine_sections_) sections.push_back(s);
    if (node.is_table() || node.is_array_of_tables()) {
      std::string msg = "unknown section [" + name + "]";
      if (auto m = closest_match(name, sections))
        msg += "; did you mean [" + *m + "]?";
      else
        msg += ".";
      msg += " Allowed sections: ";
      for (std::size_t i = 0; i < sections.size(); ++i) msg += (i ? ", " : "") + ("[" + sections[i] + "]");
      issue(name, msg);
      return;
    }
    std::string msg = "key '" + name + "' = " + brief_text(node) + " is outside any section; keys belong in a section";
    // The same key name in some section is the likely intent (`seed = 3` for run.seed).
    for (const auto& t : schema_.tables())
      if (t.kind() != TableKind::Array && t.find_key(name)) {
        msg += "; did you mean " + t.path() + "." + name + "?";
        break;
      }
    issue_at_key(k, name, msg);
  }

  // A sub-table entry `node` named by spec `t`, written into `parent_out[name]`.
  void table_entry(const TableSpec& t, const toml::node& node, const std::string& path, toml::table& parent_out,
                   const std::string& name) {
    if (t.kind() == TableKind::Array) {
      const toml::array* arr = node.as_array();
      if (!arr || !arr->is_array_of_tables()) {
        issue(path, path + " = " + brief_text(node) + " has the wrong type (" + node_type_name(node) +
                        "); allowed: an array of tables, written [[" + t.path() + "]]");
        return;
      }
      toml::array out_arr;
      for (std::size_t i = 0; i < arr->size(); ++i) {
        toml::table elem;
        table_body(t, *(*arr)[i].as_table(), path + "[" + std::to_string(i) + "]", elem);
        out_arr.push_back(std::move(elem));
      }
      if (arr->size() < t.min_count)
        issue(path, "[[" + t.path() + "]] appears " + std::to_string(arr->size()) + " times; allowed: at least " +
                        std::to_string(t.min_count));
      parent_out.insert_or_assign(name, std::move(out_arr));
      return;
    }
    const toml::table* tbl = node.as_table();
    if (!tbl) {
      issue(path, path + " = " + brief_text(node) + " has the wrong type (" + node_type_name(node) +
                      "); allowed: a table, written [" + t.path() + "]");
      return;
    }
    toml::table out;
    table_body(t, *tbl, path, out);
    parent_out.insert_or_assign(name, std::move(out));
  }

  void table_body(const TableSpec& t, const toml::table& in, const std::string& path, toml::table& out) {
    for (auto&& [k, node] : in) {
      const std::string name(k.str());
      const std::string full = path + "." + name;
      if (const KeySpec* ks = t.find_key(name)) {
        value(*ks, node, full, out);
      } else if (const TableSpec* sub = schema_.find_table(t.path() + "." + name)) {
        table_entry(*sub, node, full, out, name);
      } else {
        std::vector<std::string> names;
        for (const auto& key : t.keys()) names.push_back(key.name);
        for (const auto& other : schema_.tables())
          if (is_direct_child(t.path(), other.path())) names.push_back(other.path().substr(t.path().size() + 1));
        std::string msg = "unknown key " + full + " = " + brief_text(node);
        if (auto m = closest_match(name, names))
          msg += "; did you mean " + path + "." + *m + "?";
        else
          msg += ".";
        msg += " Allowed in [" + t.path() + "]: ";
        for (std::size_t i = 0; i < names.size(); ++i) msg += (i ? ", " : "") + names[i];
        if (node.is_table() || node.is_array_of_tables())
          issue(full, msg);
        else
          issue_at_key(k, full, msg);
      }
    }
    for (const auto& ks : t.keys()) {
      if (in.contains(ks.name)) continue;
      if (ks.presence == Presence::Required)
        issue(path, "missing required key " + path + "." + ks.name + "; allowed: " + ks.allowed_text() + " — " +
                        ks.doc);
      else if (ks.presence == Presence::Defaulted)
        insert_default(ks, out);
    }
    fill_missing_children(&t, path, in, out);
  }

  static bool is_direct_child(const std::string& parent, const std::string& child) {
    return child.size() > parent.size() + 1 && child.compare(0, parent.size(), parent) == 0 &&
           child[parent.size()] == '.' && child.find('.', parent.size() + 1) == std::string::npos;
  }

  // Sections missing from the input are created with their defaults; optional tables stay
  // absent; arrays of tables with a minimum count are reported.
  void fill_missing_children(const TableSpec* parent, const std::string& path, const toml::table& in,
                             toml::table& out) {
    for (const auto& t : schema_.tables()) {
      const bool child = parent ? is_direct_child(parent->path(), t.path()) : t.path().find('.') == std::string::npos;
      if (!child) continue;
      const std::string name = parent ? t.path().substr(parent->path().size() + 1) : t.path();
      if (out.contains(name) || in.contains(name)) continue;  // present (possibly invalid, reported)
      const std::string full = path.empty() ? name : path + "." + name;
      if (t.kind() == TableKind::Section) {
        toml::table sub;
        table_body(t, toml::table{}, full, sub);
        out.insert_or_assign(name, std::move(sub));
      } else if (t.kind() == TableKind::Array && t.min_count > 0) {
        issue(full, "missing [[" + t.path() + "]]; allowed: at least " + std::to_string(t.min_count) + " — " + t.doc());
      }
    }
  }

  static void insert_default(const KeySpec& ks, toml::table& out) {
    std::visit(
        [&](const auto& v) {
          using V = std::decay_t<decltype(v)>;
          if constexpr (std::is_same_v<V, std::monostate>) {
          } else if constexpr (std::is_same_v<V, bool> || std::is_same_v<V, std::int64_t> ||
                               std::is_same_v<V, std::string>) {
            out.insert_or_assign(ks.name, v);
          } else if constexpr (std::is_same_v<V, double>) {
            out.insert_or_assign(ks.name, v);
          } else {
            toml::array a;
            for (const auto& e : v) {
              if constexpr (std::is_same_v<V, std::vector<bool>>)
                a.push_back(bool(e));
              else
                a.push_back(e);
            }
            out.insert_or_assign(ks.name, std::move(a));
          }
        },
        ks.default_value);
  }

  bool in_range(const KeySpec& ks, double v) const {
    if (ks.min && (ks.min_exclusive ? !(v > *ks.min) : !(v >= *ks.min))) return false;
    if (ks.max && (ks.max_exclusive ? !(v < *ks.max) : !(v <= *ks.max))) return false;
    return true;
  }

  void wrong_type(const KeySpec& ks, const toml::node& node, const std::string& full) {
    issue(full, full + " = " + brief_text(node) + " has the wrong type (" + node_type_name(node) +
                    "); allowed: " + ks.allowed_text());
  }

  void value(const KeySpec& ks, const toml::node& node, const std::string& full, toml::table& out) {
    switch (ks.type) {
      case KeyType::Bool:
        if (!node.is_boolean()) return wrong_type(ks, node, full);
        out.insert_or_assign(ks.name, node.as_boolean()->get());
        return;
      case KeyType::Int: {
        if (!node.is_integer()) return wrong_type(ks, node, full);
        const std::int64_t v = node.as_integer()->get();
        if (!in_range(ks, double(v)))
          return issue(full, full + " = " + toml_int(v) + " is out of range; allowed: " + ks.allowed_text());
        out.insert_or_assign(ks.name, v);
        return;
      }
      case KeyType::Float: {
        if (!node.is_number()) return wrong_type(ks, node, full);
        const double v = node.is_integer() ? double(node.as_integer()->get()) : node.as_floating_point()->get();
        if (!std::isfinite(v) || !in_range(ks, v))
          return issue(full, full + " = " + brief_text(node) + " is out of range; allowed: " + ks.allowed_text());
        out.insert_or_assign(ks.name, v);
        return;
      }
      case KeyType::String:
        if (!node.is_string()) return wrong_type(ks, node, full);
        out.insert_or_assign(ks.name, node.as_string()->get());
        return;
      case KeyType::Enum: {
        if (!node.is_string()) return wrong_type(ks, node, full);
        const std::string& v = node.as_string()->get();
        for (const auto& c : ks.choices)
          if (c == v) {
            out.insert_or_assign(ks.name, v);
            return;
          }
        std::string msg = full + " = " + brief_text(toml::value<std::string>(v)) + " is not allowed; allowed: " + ks.allowed_text();
        if (auto m = closest_match(v, ks.choices)) msg += "; did you mean " + toml_string(*m) + "?";
        return issue(full, msg);
      }
      case KeyType::NumberArray:
      case KeyType::BoolArray:
      case KeyType::StringArray: array_value(ks, node, full, out); return;
    }
  }

  void array_value(const KeySpec& ks, const toml::node& node, const std::string& full, toml::table& out) {
    const toml::array* a = node.as_array();
    if (!a) return wrong_type(ks, node, full);
    if (a->size() < ks.min_length || a->size() > ks.max_length)
      return issue(full, full + " = " + brief_text(node) + " has " + std::to_string(a->size()) +
                             " elements; allowed: " + ks.allowed_text());
    toml::array result;
    bool ok = true;
    for (std::size_t i = 0; i < a->size(); ++i) {
      const toml::node& e = (*a)[i];
      std::string elem = full + "[" + std::to_string(i) + "]";
      if (i < ks.element_names.size()) elem += " (" + ks.element_names[i] + ")";
      auto bad_type = [&] {
        issue(full, elem + " = " + brief_text(e) + " has the wrong type (" + node_type_name(e) +
                        "); allowed: " + ks.allowed_text());
        ok = false;
      };
      if (ks.type == KeyType::BoolArray) {
        if (!e.is_boolean()) { bad_type(); continue; }
        result.push_back(e.as_boolean()->get());
      } else if (ks.type == KeyType::StringArray) {
        if (!e.is_string()) { bad_type(); continue; }
        const std::string& v = e.as_string()->get();
        bool allowed = ks.choices.empty();
        for (const auto& c : ks.choices) allowed = allowed || c == v;
        if (!allowed) {
          std::string msg = elem + " = " + brief_text(toml::value<std::string>(v)) + " is not allowed; allowed: " + ks.allowed_text();
          if (auto m = closest_match(v, ks.choices)) msg += "; did you mean " + toml_string(*m) + "?";
          issue(full, msg);
          ok = false;
          continue;
        }
        result.push_back(v);
      } else if (ks.element_integer) {
        if (!e.is_integer()) { bad_type(); continue; }
        const std::int64_t v = e.as_integer()->get();
        if (!in_range(ks, double(v))) {
          issue(full, elem + " = " + toml_int(v) + " is out of range; allowed: " + ks.allowed_text());
          ok = false;
          continue;
        }
        result.push_back(v);
      } else {
        if (!e.is_number()) { bad_type(); continue; }
        const double v = e.is_integer() ? double(e.as_integer()->get()) : e.as_floating_point()->get();
        if (!std::isfinite(v) || !in_range(ks, v)) {
          issue(full, elem + " = " + brief_text(e) + " is out of range; allowed: " + ks.allowed_text());
          ok = false;
          continue;
        }
        result.push_back(v);
      }
    }
    if (ok) out.insert_or_assign(ks.name, std::move(result));
  }

  const toml::table& doc_;
  const Origins& origins_;
  const std::string& source_;
  const Schema& schema_;
  bool engine_known_;
  std::span<const std::string> engine_sections_;
  std::vector<SceneIssue>& issues_;
};

class CheckSink final : public SceneCheck {
public:
  CheckSink(const toml::table& doc, const Origins& origins, const std::string& source, std::vector<SceneIssue>& issues)
      : doc_(doc), origins_(origins), source_(source), issues_(issues) {}
  void fail(std::string_view key_path, std::string message) override {
    issues_.push_back({locate(doc_, key_path, origins_, source_), std::string(key_path), std::move(message)});
  }

private:
  const toml::table& doc_;
  const Origins& origins_;
  const std::string& source_;
  std::vector<SceneIssue>& issues_;
};

}  // namespace

ValidatedScene validate_scene(const toml::table& doc, const Origins& origins, const std::string& source_name,
                              const SchemaCatalog& catalog, std::vector<SceneIssue>& issues) {
  ValidatedScene result;
  const toml::node* engine_node = toml::at_path(doc, "run.engine").node();
  const Schema* schema = &catalog.common();
  if (engine_node && engine_node->is_string()) {
    if (const Schema* s = catalog.for_engine(engine_node->as_string()->get())) {
      result.engine = engine_node->as_string()->get();
      schema = s;
    }
  }
  result.schema = schema;
  const std::size_t before = issues.size();
  Validator v(doc, origins, source_name, *schema, !result.engine.empty(), catalog.engine_sections(), issues);
  result.effective = v.run();
  // Cross-key rules read typed values, so they run only on a scene whose keys are all valid.
  if (issues.size() == before && !result.engine.empty()) {
    auto impl = std::make_shared<Scene::Impl>();
    impl->table = result.effective;
    impl->engine = result.engine;
    impl->schema = schema;
    const Scene scene(impl);
    CheckSink sink(doc, origins, source_name, issues);
    for (const auto& check : schema->checks()) check(scene, sink);
  }
  return result;
}

}  // namespace grainflow::scenes
