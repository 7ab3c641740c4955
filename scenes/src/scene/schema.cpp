#include "scenes/src/scene/schema.hpp"

#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "engine/core/error.hpp"
#include "scenes/src/scene/toml_text.hpp"

namespace grainflow::scenes {

std::string_view key_type_name(KeyType t) {
  switch (t) {
    case KeyType::Bool: return "boolean";
    case KeyType::Int: return "integer";
    case KeyType::Float: return "number";
    case KeyType::String: return "string";
    case KeyType::Enum: return "string";
    case KeyType::NumberArray: return "array of numbers";
    case KeyType::BoolArray: return "array of booleans";
    case KeyType::StringArray: return "array of strings";
  }
  return "?";
}

namespace {

std::string num_text(double v, bool integer) {
  if (integer && std::abs(v) < 9.0e15) return toml_int(static_cast<std::int64_t>(v));
  return toml_float(v);
}

std::string join_choices(const std::vector<std::string>& choices) {
  std::string s;
  for (std::size_t i = 0; i < choices.size(); ++i) s += (i ? " | " : "") + toml_string(choices[i]);
  return s;
}

std::string default_text(const KeySpec& k) {
  struct V {
    const KeySpec& k;
    std::string operator()(std::monostate) const { return ""; }
    std::string operator()(bool b) const { return b ? "true" : "false"; }
    std::string operator()(std::int64_t i) const { return toml_int(i); }
    std::string operator()(double d) const { return toml_float(d); }
    std::string operator()(const std::string& s) const { return toml_string(s); }
    std::string operator()(const std::vector<double>& v) const {
      std::string s = "[";
      for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + toml_float(v[i]);
      return s + "]";
    }
    std::string operator()(const std::vector<std::int64_t>& v) const {
      std::string s = "[";
      for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + toml_int(v[i]);
      return s + "]";
    }
    std::string operator()(const std::vector<bool>& v) const {
      std::string s = "[";
      for (std::size_t i = 0; i < v.size(); ++i) s += std::string(i ? ", " : "") + (v[i] ? "true" : "false");
      return s + "]";
    }
    std::string operator()(const std::vector<std::string>& v) const {
      std::string s = "[";
      for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + toml_string(v[i]);
      return s + "]";
    }
  };
  return std::visit(V{k}, k.default_value);
}

}  // namespace

std::string KeySpec::range_text() const {
  const bool integer = type == KeyType::Int || element_integer;
  std::string s;
  if (min && max) {
    s = num_text(*min, integer) + (min_exclusive ? " < " : " ≤ ") + "value" + (max_exclusive ? " < " : " ≤ ") +
        num_text(*max, integer);
  } else if (min) {
    s = std::string("value") + (min_exclusive ? " > " : " ≥ ") + num_text(*min, integer);
  } else if (max) {
    s = std::string("value") + (max_exclusive ? " < " : " ≤ ") + num_text(*max, integer);
  }
  return s;
}

std::string KeySpec::allowed_text() const {
  std::string s;
  const std::string range = range_text();
  auto length_text = [&] {
    if (min_length == max_length) return std::to_string(min_length) + " ";
    if (max_length == SIZE_MAX) return min_length > 0 ? "at least " + std::to_string(min_length) + " " : std::string();
    return std::to_string(min_length) + " to " + std::to_string(max_length) + " ";
  };
  auto names = [&] {
    if (element_names.empty()) return std::string();
    std::string n = " [";
    for (std::size_t i = 0; i < element_names.size(); ++i) n += (i ? ", " : "") + element_names[i];
    return n + "]";
  };
  switch (type) {
    case KeyType::Bool: s = "true or false"; break;
    case KeyType::Int: s = range.empty() ? "an integer" : "an integer with " + range; break;
    case KeyType::Float: s = range.empty() ? "a finite number" : "a number with " + range; break;
    case KeyType::String: s = "a string"; break;
    case KeyType::Enum: s = "one of " + join_choices(choices); break;
    case KeyType::NumberArray:
      s = "an array of " + length_text() + (element_integer ? "integers" : "numbers") + names();
      if (!range.empty()) s += ", each with " + range;
      break;
    case KeyType::BoolArray: s = "an array of " + length_text() + "booleans" + names(); break;
    case KeyType::StringArray:
      s = "an array of " + length_text() + "strings";
      if (!choices.empty()) s += " from " + join_choices(choices);
      break;
  }
  if (!note.empty()) s += " (" + note + ")";
  return s;
}

const KeySpec* TableSpec::find_key(std::string_view name) const {
  for (const auto& k : keys_)
    if (k.name == name) return &k;
  return nullptr;
}

KeySpec& TableSpec::add(std::string_view key_path, KeySpec k) {
  const auto dot = key_path.rfind('.');
  if (dot == std::string_view::npos || key_path.substr(0, dot) != path_)
    throw std::logic_error("scene schema: key " + std::string(key_path) + " declared in table [" + path_ + "]");
  k.name = std::string(key_path.substr(dot + 1));
  if (find_key(k.name)) throw std::logic_error("scene schema: key " + path_ + "." + k.name + " registered twice");
  keys_.push_back(std::move(k));
  return keys_.back();
}

KeySpec& TableSpec::add_bool(Key<bool> key, bool def, std::string doc) {
  KeySpec k;
  k.type = KeyType::Bool, k.default_value = def, k.doc = std::move(doc);
  return add(key.path, std::move(k));
}

KeySpec& TableSpec::add_int_impl(std::string_view path, std::int64_t def, std::string doc, std::string unit) {
  KeySpec k;
  k.type = KeyType::Int, k.default_value = def, k.doc = std::move(doc);
  k.unit = std::move(unit);
  return add(path, std::move(k));
}

KeySpec& TableSpec::add_float(Key<double> key, double def, std::string doc, std::string unit) {
  KeySpec k;
  k.type = KeyType::Float, k.default_value = def, k.doc = std::move(doc);
  k.unit = std::move(unit);
  return add(key.path, std::move(k));
}

KeySpec& TableSpec::add_string(Key<std::string> key, std::string def, std::string doc) {
  KeySpec k;
  k.type = KeyType::String, k.default_value = std::move(def), k.doc = std::move(doc);
  return add(key.path, std::move(k));
}

KeySpec& TableSpec::add_enum(Key<std::string> key, std::vector<std::string> choices, std::string def,
                             std::string doc) {
  KeySpec k;
  k.type = KeyType::Enum, k.choices = std::move(choices);
  k.default_value = std::move(def), k.doc = std::move(doc);
  return add(key.path, std::move(k));
}

KeySpec& TableSpec::add_float_array_impl(std::string_view path, std::vector<double> def,
                                         std::vector<std::string> element_names, std::string doc, std::string unit) {
  KeySpec k;
  k.type = KeyType::NumberArray, k.doc = std::move(doc), k.unit = std::move(unit);
  k.min_length = k.max_length = element_names.size();
  k.element_names = std::move(element_names);
  k.default_value = std::move(def);
  return add(path, std::move(k));
}

KeySpec& TableSpec::add_int_array_impl(std::string_view path, std::vector<std::int64_t> def,
                                       std::vector<std::string> element_names, std::string doc, std::string unit) {
  KeySpec k;
  k.type = KeyType::NumberArray, k.element_integer = true;
  k.doc = std::move(doc), k.unit = std::move(unit);
  k.min_length = k.max_length = element_names.size();
  k.element_names = std::move(element_names);
  k.default_value = std::move(def);
  return add(path, std::move(k));
}

KeySpec& TableSpec::add_bool_array_impl(std::string_view path, std::vector<bool> def,
                                        std::vector<std::string> element_names, std::string doc) {
  KeySpec k;
  k.type = KeyType::BoolArray, k.doc = std::move(doc);
  k.min_length = k.max_length = element_names.size();
  k.element_names = std::move(element_names);
  k.default_value = std::move(def);
  return add(path, std::move(k));
}

KeySpec& TableSpec::add_string_array(Key<std::vector<std::string>> key, std::vector<std::string> choices,
                                     std::vector<std::string> def, std::string doc) {
  KeySpec k;
  k.type = KeyType::StringArray, k.choices = std::move(choices);
  k.default_value = std::move(def), k.doc = std::move(doc);
  return add(key.path, std::move(k));
}

TableSpec& Schema::add_table(std::string path, TableKind kind, std::string doc) {
  if (find_table(path)) throw std::logic_error("scene schema: table [" + path + "] registered twice");
  const auto dot = path.rfind('.');
  if (dot != std::string::npos) {
    const TableSpec* parent = find_table(std::string_view(path).substr(0, dot));
    if (!parent) throw std::logic_error("scene schema: parent of [" + path + "] not registered");
    if (parent->kind() == TableKind::Array)
      throw std::logic_error("scene schema: tables inside an array of tables are not supported: " + path);
  }
  tables_.emplace_back(std::move(path), kind, std::move(doc));
  return tables_.back();
}

TableSpec& Schema::table(std::string_view path) {
  for (auto& t : tables_)
    if (t.path() == path) return t;
  throw std::logic_error("scene schema: no table [" + std::string(path) + "]");
}

const TableSpec* Schema::find_table(std::string_view path) const {
  for (const auto& t : tables_)
    if (t.path() == path) return &t;
  return nullptr;
}

const KeySpec* Schema::find_key(std::string_view dotted) const {
  const auto dot = dotted.rfind('.');
  if (dot == std::string_view::npos) return nullptr;
  const TableSpec* t = find_table(dotted.substr(0, dot));
  return t ? t->find_key(dotted.substr(dot + 1)) : nullptr;
}

std::string describe_schema(const Schema& s) {
  std::string out;
  for (const auto& t : s.tables()) {
    out += t.kind() == TableKind::Array ? "[[" + t.path() + "]]" : "[" + t.path() + "]";
    if (t.kind() == TableKind::Optional) out += "  (optional table)";
    out += "  " + t.doc() + "\n";
    for (const auto& k : t.keys()) {
      out += "  " + k.name + ": " + k.allowed_text();
      if (!k.unit.empty()) out += ", unit " + k.unit;
      switch (k.presence) {
        case Presence::Defaulted: out += "; default " + default_text(k); break;
        case Presence::Required: out += "; required"; break;
        case Presence::Optional: out += "; optional"; break;
      }
      out += "\n      " + k.doc + "\n";
    }
  }
  return out;
}

}  // namespace grainflow::scenes
