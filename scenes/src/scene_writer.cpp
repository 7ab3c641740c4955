// Scene::to_toml: the effective scene as a TOML file in schema order, every key with its
// value (defaults included) and its doc as a comment, so DIR/scene.toml both reproduces the
// run (`grainflow run DIR/scene.toml`) and explains it.
#include "scenes/src/scene.hpp"
#include "scenes/src/scene_impl.hpp"
#include "scenes/src/scene_schema.hpp"
#include "scenes/src/scene_validate.hpp"

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

void write_keys(const TableSpec& spec, const toml::table& t, std::string& out) {
  for (const auto& k : spec.keys()) {
    const toml::node* n = t.get(k.name);
    if (!n) continue;  // optional key not given
    out += k.name + " = " + node_text(*n);
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
        write_keys(spec, *elem.as_table(), out);
      }
    } else {
      out += "\n[" + spec.path() + "]  # " + one_line(spec.doc()) + "\n";
      write_keys(spec, *n->as_table(), out);
    }
  }
  return out;
}

}  // namespace grainflow::scenes
