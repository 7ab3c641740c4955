#include "scenes/src/scene/overrides.hpp"

#include <cctype>
#include <optional>

#include "engine/core/error.hpp"

namespace grainflow::scenes {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

struct Segment {
  std::string name;
  std::optional<std::size_t> index;  // name[index]
};

// "system.group[1].radius" -> {system}, {group, 1}, {radius}; nullopt when malformed.
std::optional<std::vector<Segment>> split_key(std::string_view key) {
  std::vector<Segment> out;
  std::size_t pos = 0;
  while (pos <= key.size()) {
    const std::size_t dot = std::min(key.find('.', pos), key.size());
    std::string_view seg = key.substr(pos, dot - pos);
    Segment s;
    if (const auto br = seg.find('['); br != std::string_view::npos) {
      if (seg.back() != ']' || br + 2 > seg.size() - 1) return std::nullopt;
      std::size_t idx = 0;
      for (char c : seg.substr(br + 1, seg.size() - br - 2)) {
        if (!std::isdigit(static_cast<unsigned char>(c))) return std::nullopt;
        idx = idx * 10 + std::size_t(c - '0');
      }
      s.index = idx;
      seg = seg.substr(0, br);
    }
    if (seg.empty()) return std::nullopt;
    for (char c : seg)
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') return std::nullopt;
    s.name = std::string(seg);
    out.push_back(std::move(s));
    pos = dot + 1;
  }
  return out;
}

// Copies a node polymorphically (toml++ nodes are copied through their concrete type).
void assign(toml::table& t, const std::string& name, const toml::node& n) {
  n.visit([&](const auto& concrete) { t.insert_or_assign(name, concrete); });
}

}  // namespace

Override parse_override(std::string_view arg) {
  const auto eq = arg.find('=');
  if (eq == std::string_view::npos)
    throw Error("--set " + std::string(arg) + ": expected section.key=value, e.g. --set run.seed=3");
  Override o;
  o.key = std::string(trim(arg.substr(0, eq)));
  o.value = std::string(trim(arg.substr(eq + 1)));
  o.text = "--set " + std::string(arg);
  if (o.key.empty() || !split_key(o.key))
    throw Error(o.text + ": '" + o.key +
                "' is not a key path; allowed: section.key (letters, digits, _ and -), e.g. render.size or "
                "system.group[0].radius");
  return o;
}

void apply_override(toml::table& doc, const Override& o, Origins& origins, std::vector<SceneIssue>& issues) {
  auto fail = [&](std::string msg) { issues.push_back({o.text, o.key, std::move(msg)}); };

  // The value: TOML if it reads as TOML, else a plain string for convenience.
  std::optional<toml::table> parsed;
  try {
    parsed = toml::parse("v = " + o.value, std::string_view(o.text));
  } catch (const toml::parse_error& e) {
    const char first = o.value.empty() ? '\0' : o.value.front();
    if (first == '"' || first == '\'' || first == '[' || first == '{')
      return fail(o.key + " = " + o.value + " is not a valid TOML value: " + std::string(e.description()));
  }
  toml::table plain;
  if (!parsed || parsed->size() != 1 || !parsed->contains("v")) {
    plain.insert_or_assign("v", o.value);
    parsed = std::move(plain);
  }
  const toml::node& value = *parsed->get("v");

  const auto segs = *split_key(o.key);
  toml::table* cur = &doc;
  std::string path;
  for (std::size_t i = 0; i < segs.size(); ++i) {
    const Segment& s = segs[i];
    const bool last = i + 1 == segs.size();
    const std::string here = path.empty() ? s.name : path + "." + s.name;
    if (s.index) {
      toml::node* holder = cur->get(s.name);
      if (!holder)
        return fail(here + " is not in the scene, so its elements cannot be set one by one; allowed: --set " +
                    here + "=[…] with the whole array");
      toml::array* arr = holder->as_array();
      if (!arr) return fail(here + " is " + node_type_name(*holder) + ", not an array, so " + o.key + " cannot be set");
      const std::size_t idx = *s.index;
      const std::string elem = here + "[" + std::to_string(idx) + "]";
      if (last) {
        if (idx >= arr->size())
          return fail(elem + " does not exist; " + here + " has " + std::to_string(arr->size()) + " elements");
        value.visit([&](const auto& concrete) { arr->replace(arr->cbegin() + std::ptrdiff_t(idx), concrete); });
        origins[elem] = o.text;
        return;
      }
      // One past the end appends a new table: --set system.group[1].radius=… adds a group.
      if (idx == arr->size() && (arr->empty() || arr->is_array_of_tables())) {
        arr->push_back(toml::table{});
        origins[elem] = o.text;
      }
      if (idx >= arr->size())
        return fail(elem + " does not exist; " + here + " has " + std::to_string(arr->size()) + " elements");
      cur = (*arr)[idx].as_table();
      if (!cur) return fail(elem + " is not a table, so " + o.key + " cannot be set");
      path = elem;
      continue;
    }
    if (last) {
      assign(*cur, s.name, value);
      origins[here] = o.text;
      return;
    }
    toml::node* next = cur->get(s.name);
    if (!next) {
      cur->insert_or_assign(s.name, toml::table{});
      origins[here] = o.text;
      next = cur->get(s.name);
    }
    if (next->is_array_of_tables())
      return fail(here + " is an array of tables; allowed: " + here + "[i]." +
                  o.key.substr(here.size() + 1) + " with i counted from 0");
    cur = next->as_table();
    if (!cur) return fail(here + " is " + node_type_name(*next) + ", not a table, so " + o.key + " cannot be set");
    path = here;
  }
}

}  // namespace grainflow::scenes
