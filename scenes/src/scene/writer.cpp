// Scene::to_toml: the effective scene as a TOML file in schema order, every key with its
// value (defaults included) and its doc as a comment, so DIR/scene.toml both reproduces the
// run (`grainflow run DIR/scene.toml`) and explains it.
#include <filesystem>

#include "engine/core/state_digest.hpp"
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

// What the text holds: the effective scene file, or only the values a checkpoint depends on.
enum class Text { File, Fingerprint };

void write_keys(const TableSpec& spec, const toml::table& t, const std::filesystem::path& source, Text what,
                std::string& out) {
  for (const auto& k : spec.keys()) {
    const toml::node* n = t.get(k.name);
    if (!n) continue;  // optional key not given
    if (what == Text::Fingerprint && k.resumable) continue;
    out += k.name + " = " + value_text(k, *n, source);
    if (what == Text::File) {
      out += "  # " + one_line(k.doc);
      if (!k.unit.empty()) out += " [" + one_line(k.unit) + "]";
    }
    out += "\n";
  }
}

std::string scene_text(const Scene::Impl& im, Text what) {
  std::string out;
  if (what == Text::File) {
    out = "# Effective scene written by grainflow " GRAINFLOW_VERSION ": every key, defaults included.\n";
    if (!im.source.empty()) out += "# source: " + one_line(im.source.string()) + "\n";
    for (const auto& o : im.overrides) out += "# --set " + one_line(o) + "\n";
  }
  for (const auto& spec : im.schema->tables()) {
    const toml::node* n = toml::at_path(im.table, spec.path()).node();
    if (!n) continue;
    const std::string doc = what == Text::File ? "  # " + one_line(spec.doc()) : "";
    if (spec.kind() == TableKind::Array) {
      for (const auto& elem : *n->as_array()) {
        out += "\n[[" + spec.path() + "]]" + doc + "\n";
        write_keys(spec, *elem.as_table(), im.source, what, out);
      }
    } else {
      out += "\n[" + spec.path() + "]" + doc + "\n";
      write_keys(spec, *n->as_table(), im.source, what, out);
    }
  }
  return out;
}

}  // namespace

std::string Scene::to_toml() const { return scene_text(*impl_, Text::File); }

std::uint64_t Scene::fingerprint() const {
  const std::string text = scene_text(*impl_, Text::Fingerprint);
  core::StateDigest d;
  d.add_bytes(std::as_bytes(std::span(text.data(), text.size())));
  return d.value();
}

}  // namespace grainflow::scenes
