// Scene::to_toml: the effective scene as a TOML file in schema order, every key with its
// value (defaults included) and its doc as a comment, so DIR/scene.toml both reproduces the
// run (`grainflow run DIR/scene.toml`) and explains it.
#include <filesystem>

#include "scenes/src/scene/scene.hpp"
#include "scenes/src/scene/scene_impl.hpp"
#include "scenes/src/scene/schema.hpp"
#include "scenes/src/scene/validate.hpp"

#ifndef GRAINFLOW_VERSION
#define GRAINFLOW_VERSION "unknown"
#endif

namespace grainflow::scenes {

namespace {

// Comments must stay on one line.
std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

// A relative path key is resolved against the scene file's folder (how the runners read
// it), so the effective scene works from the run folder too.
std::string value_text(const KeySpec& k, const toml::node& n, const std::filesystem::path& source) {
  const auto* s = n.as_string();
  if (!k.is_path || !s || s->get().empty() || source.empty()) return node_text(n);
  const std::filesystem::path p(s->get());
  if (p.is_absolute()) return node_text(n);
  const auto resolved = std::filesystem::absolute(source.parent_path() / p).lexically_normal();
  return node_text(toml::value<std::string>(resolved.string()));
}

void write_keys(const TableSpec& spec, const toml::table& t, const std::filesystem::path& source, std::string& out) {
  for (const auto& k : spec.keys()) {
    const toml::node* n = t.get(k.name);
    if (!n) continue;  // optional key not given
    out += k.name + " = " + value_text(k, *n, source);
    out += "  # " + one_line(k.doc);
    if (!k.unit.empty()) out += " [" + one_line(k.unit) + "]";
    out += "\n";
  }
}

}  // namespace

std::string Scene::to_toml() const {
  const Impl& im = *impl_;
  std::string out = "# Effective scene written by grainflow " GRAINFLOW_VERSION
                    ": every key, defaults included.\n";
  if (!im.source.empty()) out += "# source: " + one_line(im.source.string()) + "\n";
  for (const auto& o : im.overrides) out += "# --set " + one_line(o) + "\n";
  for (const auto& spec : im.schema->tables()) {
    const toml::node* n = toml::at_path(im.table, spec.path()).node();
    if (!n) continue;
    if (spec.kind() == TableKind::Array) {
      for (const auto& elem : *n->as_array()) {
        out += "\n[[" + spec.path() + "]]  # " + one_line(spec.doc()) + "\n";
        write_keys(spec, *elem.as_table(), im.source, out);
      }
    } else {
      out += "\n[" + spec.path() + "]  # " + one_line(spec.doc()) + "\n";
      write_keys(spec, *n->as_table(), im.source, out);
    }
  }
  return out;
}

}  // namespace grainflow::scenes
